"""lanecast.yt: render yt datasets (yt 4, Debian's python3-yt).

Particle and SPH datasets (``yt.load_particles``, SPH frontends) become lanecast Particles:
positions in code units (``code_length``), radii from the smoothing lengths where the dataset
has them (r = h / 2 by default, so the Gaussian truncated at sigma = 2 radii reaches h), else
one radius from the mean interparticle spacing. Grid datasets (``yt.load_uniform_grid`` and
the top level of others) become a Grid of the level-0 covering grid: nodes at the cell centres,
spacing and origin in code units, the field's values in the units yt gives it (or units=...).

    import lanecast.yt
    img = lanecast.yt.render(ds, ("gas", "density"), width=512)
"""

import numpy as np

import lanecast as lc


def _ptype(ds, field):
    if isinstance(field, tuple) and field[0] in ds.particle_types:
        return field[0]
    sph = tuple(getattr(ds, "_sph_ptypes", ()) or ())
    if sph:
        return sph[0]
    types = [t for t in ds.particle_types if t != "all"]
    return types[0] if types else None


def _is_particles(ds, field):
    if isinstance(field, tuple) and field[0] in ds.particle_types:
        return True
    return not hasattr(ds.index, "grids") and bool(ds.particle_types)


def particles(ds, field=None, device=None, *, radius_scale=0.5, radius=None, ptype=None, units=None):
    """The particles of ptype (default: the SPH type, else the first) as lanecast Particles,
    weighted by `field` (a particle field of that type, or its name; None = unit weights) in
    `units` (default: the units yt gives the field)."""
    ptype = ptype or _ptype(ds, field)
    if ptype is None:
        raise ValueError("lanecast.yt: the dataset has no particle type")
    ad = ds.all_data()
    pos = np.ascontiguousarray(ad[ptype, "particle_position"].to("code_length").d, dtype=np.float32)
    if radius is not None:
        radii = float(radius)
    elif (ptype, "smoothing_length") in ds.field_list:
        radii = ad[ptype, "smoothing_length"].to("code_length").d * radius_scale
    else:
        width = (ds.domain_right_edge - ds.domain_left_edge).to("code_length").d
        radii = float(np.prod(width) / max(len(pos), 1)) ** (1.0 / 3.0) * radius_scale
    values = None
    if field is not None:
        name = field[1] if isinstance(field, tuple) else field
        v = ad[ptype, name]
        values = (v.to(units) if units is not None else v).d
    return lc.Particles(device, pos, radii=radii, values=values)


def grid(ds, field=None, device=None, *, units=None):
    """The level-0 covering grid of `field` (default: the dataset's first field) as a Grid,
    in `units` (default: the units yt gives the field)."""
    if field is None:
        field = ds.field_list[0]
    dims = ds.domain_dimensions
    left = ds.domain_left_edge.to("code_length").d
    dx = (ds.domain_right_edge.to("code_length").d - left) / dims
    cg = ds.covering_grid(level=0, left_edge=ds.domain_left_edge, dims=dims)
    v = cg[field]
    data = np.asarray((v.to(units) if units is not None else v).d)  # indexed [i, j, k] = x, y, z
    return lc.Grid(device, data, spacing=tuple(dx), origin=tuple(left + dx / 2), order="xyz")


def volume(ds, field=None, device=None, **kw):
    """A lanecast volume of a yt dataset: Particles for particle/SPH data (or a particle
    field), else a Grid. Keywords go to particles() or grid()."""
    if _is_particles(ds, field):
        return particles(ds, field, device, **kw)
    return grid(ds, field, device, **kw)


def render(ds, field=None, device=None, **render_options):
    """Renders volume(ds, field) with lanecast.render's options; returns the Image."""
    return lc.render(volume(ds, field, device), **render_options)
