"""lanecast.Camera: the view of a render (SPEC.md "Camera and rays")."""

from . import _lanecast as _lc

_PROJECTIONS = {"perspective": 0, "orthographic": 1}


class Camera:
    """A pinhole (or orthographic) camera: eye, at, up (x, y, z), vertical field of view fov
    in degrees (None = 40), or projection='orthographic' with height = the image plane's height
    in world units (0 = frame the data). eye == at asks the library for its default view."""

    def __init__(self, eye, at, up=None, fov=None, projection="perspective", height=0.0):
        if projection not in _PROJECTIONS:
            raise ValueError(f"projection: {projection!r} is not 'perspective' or 'orthographic'")
        self.eye = tuple(float(x) for x in eye)
        self.at = tuple(float(x) for x in at)
        self.up = (0.0, 1.0, 0.0) if up is None else tuple(float(x) for x in up)
        self.fov = 40.0 if fov is None else float(fov)
        self.projection = projection
        self.height = float(height)

    @classmethod
    def frame(cls, bounds, azimuth=35.0, elevation=25.0, fov=None, projection="perspective", height=0.0):
        """The camera that looks at the centre of bounds (a volume, or ((x0, y0, z0), (x1, y1, z1)))
        from azimuth degrees around +y (0 = from +z, 90 = from +x) and elevation degrees above the
        xz plane, at the distance where the bounding sphere fills the view (lc_camera_frame)."""
        if hasattr(bounds, "info"):
            bounds = bounds.info["bounds"]
        fov = 40.0 if fov is None else float(fov)
        eye, at, up = _lc.camera_frame(tuple(tuple(b) for b in bounds), float(azimuth), float(elevation))
        return cls(eye, at, up=up, fov=fov, projection=projection, height=height)

    def _tuple(self):
        return (_PROJECTIONS[self.projection], self.eye, self.at, self.up, self.fov, self.height)

    def __repr__(self):
        return (f"lanecast.Camera(eye={self.eye}, at={self.at}, up={self.up}, fov={self.fov}, "
                f"projection={self.projection!r}, height={self.height})")
