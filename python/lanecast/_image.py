"""lanecast.Image: a render's pixels as a NumPy array that Jupyter shows."""

import os
import tempfile

import numpy as np

from . import _lanecast as _lc


class Image(np.ndarray):
    """An (height, width, 4) float32 array of premultiplied colour and opacity (C, A), row 0
    at the top, as lc_render writes it. ``stats`` holds the render's figures (seconds, rays,
    samples, kernel_evals, nodes, leaves, passes, target, threads); ``background`` is the
    colour save() and the PNG composite onto (C + (1 - A) * background)."""

    def __array_finalize__(self, obj):
        self.stats = getattr(obj, "stats", None)
        self.background = getattr(obj, "background", (0.0, 0.0, 0.0))

    def save(self, path, *, background=None, alpha=False):
        """Writes the image through OpenImageIO, the format following the extension (.png,
        .exr, .tif, .jpg, ...; 8-bit for png/jpg, float for exr/tif). alpha=True writes an
        alpha channel instead of compositing the background. The file appears complete or
        not at all."""
        bg = self.background if background is None else background
        _lc.image_write(None, os.fspath(path), np.asarray(self), background=tuple(bg), alpha=alpha)

    def _repr_png_(self):
        if self.ndim != 3 or self.shape[2] != 4:
            return None
        with tempfile.TemporaryDirectory(prefix="lanecast-") as tmp:
            name = os.path.join(tmp, "image.png")
            self.save(name)
            with open(name, "rb") as f:
                return f.read()

    def show(self):
        """Shows the image: inline in IPython/Jupyter, else in a matplotlib window, else
        it is written to a temporary PNG whose name is printed."""
        try:
            from IPython import get_ipython
            from IPython.display import display
            if get_ipython() is not None:
                display(self)
                return
        except ImportError:
            pass
        try:
            import matplotlib.pyplot as plt
            bg = np.asarray(self.background, dtype=np.float32)
            rgb = np.asarray(self)[..., :3] + (1.0 - np.asarray(self)[..., 3:]) * bg
            plt.imshow(np.clip(rgb, 0.0, 1.0))
            plt.axis("off")
            plt.show()
            return
        except ImportError:
            pass
        fd, name = tempfile.mkstemp(prefix="lanecast-", suffix=".png")
        os.close(fd)
        self.save(name)
        print(name)
