"""lanecast.TransferFunction: colour and extinction over the normalised value (SPEC.md)."""

import os

import numpy as np

from . import _lanecast as _lc


class TransferFunction(_lc.TF):
    """A transfer function of 1 to 8 fields: piecewise linear colour [v, r, g, b] and
    extinction [v, tau] (per world unit) over the normalised value v in [0, 1], and optionally
    the value range [lo, hi] that v spans (else the render's range or the data's).

    TransferFunction(color=[(v, r, g, b), ...], opacity=[(v, tau), ...], range=None), or
    TransferFunction(fields=[dict(color=..., opacity=..., range=...), ...]) for several fields.
    """

    def __new__(cls, fields=None, *, color=None, opacity=None, range=None):
        if fields is None:
            if color is None or opacity is None:
                raise TypeError("TransferFunction: give color and opacity points, or fields=[...]")
            fields = [dict(color=color, opacity=opacity, range=range)]
        parts = []
        for f in fields:
            r = f.get("range")
            parts.append((np.asarray(f["color"], dtype=np.float32), np.asarray(f["opacity"], dtype=np.float32),
                          None if r is None else tuple(float(x) for x in r)))
        return cls._create(parts)

    @classmethod
    def preset(cls, name, fields=1, tau=1.0):
        """A built-in colour map (presets()) for `fields` fields, opacity ramping from 0 at
        v = 0.1 to tau at v = 1 (lc_tf_preset)."""
        return cls._preset(name, int(fields), float(tau))

    @classmethod
    def from_colormap(cls, name, range=None, opacity=None, tau=1.0, fields=1):
        """A colour map's colours with opacity points [(v, tau), ...] (default: the preset's
        ramp to tau) and the value range (lo, hi) they span (default: the render's or the data's)."""
        base = cls._preset(name, int(fields), float(tau))
        parts = [dict(color=f["color"], opacity=f["opacity"] if opacity is None else opacity,
                      range=range) for f in base.fields()]
        return cls(fields=parts)

    @classmethod
    def load(cls, path):
        """Reads SPEC.md's JSON transfer function or a ParaView colour-map preset (lc_tf_load)."""
        return cls._load(os.fspath(path))

    @classmethod
    def parse(cls, text, name="<string>"):
        """Parses JSON text as load() reads files; messages name `name`."""
        return cls._parse(text, name)

    @classmethod
    def auto(cls, volume, colormap=None, tau=0.0):
        """The TF that shows a volume's structure on the first try (lc_tf_auto,
        docs/FIRST-IMAGE.md); what render() uses when tf is None."""
        return cls._auto(volume, colormap, float(tau))

    def __repr__(self):
        return f"lanecast.TransferFunction(nfields={self.nfields})"
