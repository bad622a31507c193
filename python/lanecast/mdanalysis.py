"""lanecast.mdanalysis: render MDAnalysis universes and atom groups (Debian's
python3-mdanalysis).

Positions are MDAnalysis' (Angstrom, the current trajectory frame); radii are van der Waals
radii by element from MDAnalysis' own table (MDAnalysis.topology.tables.vdwradii) times
radius_scale (default 0.5, near the covalent radii lanecast's readers use; elements missing
from the topology are guessed from the atom names by MDAnalysis); selections use MDAnalysis'
selection language; fields='element' gives each element its field (in order of first
appearance, the 9th and later sharing field 7).

    import MDAnalysis as mda, lanecast.mdanalysis
    u = mda.Universe("adk.psf", "adk.dcd")
    img = lanecast.mdanalysis.render(u, select="protein", frame=10, shade="phong")
"""

import numpy as np

import lanecast as lc


def _elements(atoms):
    try:
        el = np.asarray(atoms.elements, dtype=str)
        if all(e.strip() for e in el):
            return el
    except (AttributeError, ValueError):
        pass
    from MDAnalysis.topology.guessers import guess_types
    return np.asarray(guess_types(atoms.names), dtype=str)


def volume(atoms, device=None, *, select=None, frame=None, fields=None, values=None, radius=None,
           radius_scale=0.5):
    """A lanecast Particles of a Universe or AtomGroup. select: an MDAnalysis selection string;
    frame: the trajectory frame to read first (None = the current one); fields: None (one
    field) or 'element'; values: None or an AtomGroup attribute name ('charges', 'masses',
    'tempfactors', ...) for the Gaussians' weights; radius: one radius for all atoms instead."""
    from MDAnalysis.topology.tables import vdwradii
    ag = atoms.atoms  # a Universe's atoms, or the AtomGroup itself
    if frame is not None:
        ag.universe.trajectory[frame]
    if select is not None:
        ag = ag.select_atoms(select)
    if len(ag) == 0:
        raise ValueError("atoms: the selection holds no atom")
    el = _elements(ag)
    if radius is None:
        default = vdwradii.get("C", 1.7)
        radii = np.array([vdwradii.get(e.upper(), default) for e in el], np.float32) * radius_scale
    else:
        radii = float(radius)
    ids = None
    if fields == "element":
        order = {}
        for e in el:
            order.setdefault(e.upper(), min(len(order), lc.MAX_FIELDS - 1))
        ids = np.array([order[e.upper()] for e in el], np.uint8)
    elif fields is not None:
        raise ValueError(f"fields: {fields!r} is not None or 'element'")
    vals = None if values is None else np.asarray(getattr(ag, values), np.float32)
    return lc.Particles(device, ag.positions, radii=radii, values=vals, fields=ids)


def render(atoms, device=None, *, select=None, frame=None, fields=None, values=None, radius=None,
           radius_scale=0.5, **render_options):
    """Renders volume(atoms, ...) with lanecast.render's options; returns the Image."""
    vol = volume(atoms, device, select=select, frame=frame, fields=fields, values=values, radius=radius,
                 radius_scale=radius_scale)
    if "tf" not in render_options and vol.info["nfields"] > 1:
        # several fields: the warm/cool demo map, peak extinction 1 / the largest radius (as lc_tf_auto)
        render_options["tf"] = lc.TransferFunction.preset("demo", vol.info["nfields"], 1.0 / vol.info["radius"][1])
    return lc.render(vol, **render_options)
