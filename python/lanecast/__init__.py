"""lanecast: CPU volume ray casting of particles, structured grids and RBF sets.

NumPy arrays in, images out (docs/PYTHON.md)::

    import lanecast as lc
    dev = lc.Device()
    vol = lc.Particles(dev, positions, radii=1.0)
    img = lc.render(vol, width=800, height=600, shade="phong")
    img.save("a.png")          # or show it in Jupyter: img

Coordinates (positions, spacing, origin, eye, at, up, bounds) are x, y, z as on the
command line. A Grid's array is read in NumPy's C order by default (axis 0 = z).
The GIL is released during loading, BVH builds, rendering and encoding; Ctrl-C
stops a render within a tile and raises KeyboardInterrupt.
"""

from . import _lanecast as _lc
from ._lanecast import (
    Device,
    Volume,
    Particles,
    Grid,
    RBFSet,
    Error,
    InvalidArgumentError,
    UnsupportedError,
    OutOfMemoryError,
    FileError,
    FormatError,
    InternalError,
    CancelledError,
    TimeoutError,
    MAX_FIELDS,
    MAX_PLANES,
)
from ._lanecast import Warning  # noqa: A004 (lanecast.Warning: the library's log warnings)
from ._camera import Camera
from ._image import Image
from ._tf import TransferFunction

__version__ = _lc.version

__all__ = [
    "Device", "Volume", "Particles", "Grid", "RBFSet", "TransferFunction", "Camera", "Image",
    "load", "render", "encode", "probe", "select_check", "targets", "formats", "features", "presets",
    "Error", "InvalidArgumentError", "UnsupportedError", "OutOfMemoryError", "FileError",
    "FormatError", "InternalError", "CancelledError", "TimeoutError", "MAX_FIELDS", "MAX_PLANES",
]

_MODES = {"dvr": 0, "mip": 1, "iso": 2, "slice": 3}
_SHADING = {None: 0, False: 0, "none": 0, True: 1, "diffuse": 1, "phong": 2}
_METHODS = {None: 0, "default": 0, "coherent": 1, "direct": 2, "bvh": 3, "brute": 4}


def targets():
    """Every SIMD target: a list of dicts (name, lanes, compiled, supported), as `lanecast targets`."""
    return _lc.targets()


def formats():
    """Every file format of this build (name, kind, extensions, options, description, available, package)."""
    return _lc.formats()


def features():
    """The optional libraries of this build (name, library, available, package, description)."""
    return _lc.features()


def select_check(expr):
    """Checks an atom selection (the `select` load option) without a file: InvalidArgumentError
    naming the position of what is wrong."""
    _lc.select_check(expr)


def presets():
    """The names of the built-in colour maps (TransferFunction.preset, from_colormap)."""
    return _lc.presets()


def _option_text(value):
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, (list, tuple)):
        return ",".join(_option_text(v) for v in value)
    return str(value)


def load(device, path, *, format=None, frame=0, companion=None, topology=None, progress=None, **options):
    """Reads a file through lanecast's readers (every format of `formats()`) into a volume.

    options are the format's load options as on the command line's --option, e.g.
    ``load(dev, "snap.hdf5", types=[0], value="rho")``, ``select="protein"``,
    ``fields="cpk"``, ``radius=1.5``, ``size=(64, 64, 32)`` (lists are joined by commas).
    topology (or companion): a second file, such as a DCD trajectory's PSF. progress: a
    callable taking the fraction read (0..1). Errors name the file and the line or byte.
    """
    if topology is not None and companion is not None:
        raise TypeError("load: give topology or companion, not both")
    opts = {str(k): _option_text(v) for k, v in options.items()}
    return _lc.load(device, path, format=format, companion=topology if topology is not None else companion,
                    frame=frame, options=opts, progress=progress)


def probe(path, *, format=None, companion=None, **options):
    """The format, kind, frame count and compression of a file, without reading its data."""
    opts = {str(k): _option_text(v) for k, v in options.items()}
    return _lc.probe(path, format=format, companion=companion, options=opts)


def _resolve_tf(volume, tf):
    if tf is None or isinstance(tf, str) and tf in _lc.presets():
        # the first-image rule of lc_tf_auto (docs/FIRST-IMAGE.md), made once per volume
        cache = volume.__dict__.setdefault("_auto_tfs", {})
        if tf not in cache:
            cache[tf] = TransferFunction.auto(volume, colormap=tf)
        return cache[tf]
    if isinstance(tf, str) or hasattr(tf, "__fspath__"):
        return TransferFunction.load(tf)
    return tf


def _camera(volume, camera, eye, at, up, fov, ortho, view):
    if camera is not None:
        if any(x is not None for x in (eye, at, view)):
            raise TypeError("render: give camera, eye/at or view, not several")
        return camera
    if (eye is None) != (at is None):
        raise TypeError("render: give both eye and at (or neither, to frame the data)")
    if eye is not None and view is not None:
        raise TypeError("render: give eye/at or view, not both")
    projection = "perspective" if ortho is None else "orthographic"
    height = 0.0 if ortho is None else float(ortho)
    if eye is not None:
        return Camera(eye, at, up=up, fov=fov, projection=projection, height=height)
    if view is not None:
        az, el = view
        return Camera.frame(volume, azimuth=az, elevation=el, fov=fov, projection=projection, height=height)
    # all zero: the library frames the data from its default view (35, 25)
    return Camera((0, 0, 0), (0, 0, 0), up=up, fov=fov, projection=projection, height=height)


def render(volume, tf=None, width=512, height=None, *, camera=None, eye=None, at=None, up=None, fov=None,
           ortho=None, view=None, range=None, mode="dvr", iso=None, field=0, planes=None, dt=0.0,
           alpha_stop=0.0, shade=None, lighting=None, method=None, packet=0, tile=0, pixel_scale=0,
           step_scale=0.0, background=(0.0, 0.0, 0.0), device=None, out=None):
    """Renders a volume; returns an Image: an (height, width, 4) float32 array of premultiplied
    colour and opacity, row 0 at the top, with the render's statistics in ``img.stats``.

    tf: a TransferFunction, a colour-map name or a TF file (.json); None = the volume's default
    (lc_tf_auto: for grids the histogram rule of docs/FIRST-IMAGE.md). Camera: camera=Camera(...),
    or eye/at (up, fov in degrees; ortho=HEIGHT for an orthographic view, 0 = frame the data),
    or view=(azimuth, elevation) framing the data; nothing = the default three-quarter view.
    mode: 'dvr', 'mip', 'iso' (iso=VALUE, field=N) or 'slice' (planes=[(point, normal), ...],
    field=N). shade: None, 'diffuse' or 'phong'; lighting=(ka, kd, ks[, phong_exp]).
    method: 'coherent', 'direct', 'bvh' or 'brute' (None = the kind's fastest). Zero means the
    library's default for dt, alpha_stop, packet, tile. device: the device to render on (default:
    the volume's; renders on one device run one at a time). background: what save() and the
    PNG composite onto.
    """
    if height is None:
        height = width
    try:
        m = _MODES[mode]
    except (KeyError, TypeError):
        raise ValueError(f"mode: {mode!r} is not one of 'dvr', 'mip', 'iso', 'slice'") from None
    if m == 2 and iso is None:
        raise ValueError("iso: mode 'iso' needs iso=VALUE")
    if m == 3 and not planes:
        raise ValueError("planes: mode 'slice' needs planes=[(point, normal), ...]")
    try:
        shading = _SHADING[shade]
        meth = _METHODS[method]
    except (KeyError, TypeError):
        raise ValueError(f"shade/method: {shade!r}/{method!r}: shade is None, 'diffuse' or 'phong'; method "
                         "None, 'coherent', 'direct', 'bvh' or 'brute'") from None
    if lighting is not None:
        lighting = tuple(lighting)
        if len(lighting) == 3:
            lighting = lighting + (16,)
        if len(lighting) != 4:
            raise ValueError("lighting: expected (ka, kd, ks) or (ka, kd, ks, phong_exp)")
    if not isinstance(volume, Volume):
        raise TypeError(f"volume: expected a lanecast volume, got {type(volume).__name__}")
    cam = _camera(volume, camera, eye, at, up, fov, ortho, view)
    rgba, stats = _lc.render(device if device is not None else volume.device, volume, _resolve_tf(volume, tf),
                             int(width), int(height), cam._tuple(), range=None if range is None else tuple(range),
                             mode=m, iso=0.0 if iso is None else float(iso), field=int(field), planes=planes,
                             dt=float(dt), alpha_stop=float(alpha_stop), shading=shading, lighting=lighting,
                             method=meth, packet=int(packet), tile=int(tile), pixel_scale=int(pixel_scale),
                             step_scale=float(step_scale), out=out)
    img = rgba.view(Image)
    img.stats = stats
    img.background = tuple(background)
    return img


def encode(device=None, points=None, values=None, *, grid=None, order="zyx", spacing=None, origin=None, path=None,
           max_error=0.02, max_rbfs=0, centre="mean", fit_range=None, fit_samples=0, lm_samples=0, local_rbfs=0,
           seed=0, progress=None, eps=0.0, domain=None, accel=None):
    """Fits an RBF set to samples (Jang et al. 2004 sec. 4) and returns it as an RBFSet whose
    ``report`` holds the fit's figures (rbfs, rms, max_error, iterations, reached, seconds).

    The samples: points (N, 3) with values (N,), or grid (a 3-D array, read as Grid reads it, with
    spacing and origin), or path (a CSV/VTK samples file or any volume lanecast reads).
    progress: a callable receiving a dict after each iteration (iteration, rbfs, rms, seconds,
    target, max_rbfs, polish), or True to print a line per iteration to stderr. The encoder
    cannot be cancelled (the C API has no cancel for it). eps, domain, accel: of the RBFSet made.
    """
    if progress is True:
        import sys

        def progress(p):
            print(f"lanecast encode: {p['rbfs']} RBFs, rms {p['rms']:.4g} (target {p['target']:.4g}), "
                  f"{p['seconds']:.1f} s", file=sys.stderr)
    dev = device
    centres, widths, weights, bias, report = _lc.encode(
        dev, points=points, values=values, grid=grid, order=order, spacing=spacing, origin=origin, path=path,
        max_error=float(max_error), max_rbfs=int(max_rbfs), centre=centre, fit_range=fit_range,
        fit_samples=int(fit_samples), lm_samples=int(lm_samples), local_rbfs=int(local_rbfs), seed=int(seed),
        progress=progress if progress else None)
    rbf = RBFSet(dev, centres, widths, weights, bias, eps=eps, domain=domain, accel=accel)
    rbf.report = report
    return rbf
