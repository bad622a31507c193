#!/usr/bin/python3
"""DICOM test series for tests/test_dicom.c, written by pydicom (and
converted by GDCM's gdcmconv to compressed transfer syntaxes) from volumes
this script knows.

usage: dicom_write.py OUT_DIR

Writes the cases into OUT_DIR and OUT_DIR/expect.txt, one line a case:

  ok NAME INPUT OPTION TYPE NX NY NZ SX SY SZ OX OY OZ WARN
      INPUT (relative to OUT_DIR; several joined by ':') loads with OPTION
      ("-" or key=value) to a TYPE grid of those sizes, spacing and origin
      (world axes, mm), whose voxels are NAME.raw (TYPE, little-endian, x
      fastest) when that file exists; WARN: "-" or a word a warning holds.
  fail NAME INPUT OPTION FILE PHRASE|PHRASE...
      loading fails with a message naming FILE (relative) and holding each PHRASE.

The expected grids come from DICOM's geometry (PS3.3 C.7.6.2.1.1): the
world position of stored pixel (column i, row j) of a slice is
ImagePositionPatient + i * PixelSpacing[1] * row direction + j *
PixelSpacing[0] * column direction; each voxel goes to the grid node at
(position - origin) / spacing, origin the smallest corner. Values are the
stored values (their Bits Stored low bits, sign-extended when signed) times
RescaleSlope plus RescaleIntercept. Exit status 77 when pydicom or NumPy
is missing."""
import os
import shutil
import subprocess
import sys

try:
    import numpy as np
    import pydicom
    from pydicom.dataset import Dataset, FileDataset, FileMetaDataset
    from pydicom.sequence import Sequence
    from pydicom.uid import ExplicitVRBigEndian, ExplicitVRLittleEndian, ImplicitVRLittleEndian
except ImportError as e:
    print("dicom_write.py: %s (Debian python3-pydicom, python3-numpy): skipped" % e)
    sys.exit(77)

out = sys.argv[1]
if os.path.isdir(out):
    shutil.rmtree(out)
os.makedirs(out)
expect = []
rng = np.random.default_rng(29)
uid_n = [0]


def uid():
    uid_n[0] += 1
    return "1.2.826.0.1.3680043.10.1029.%d" % uid_n[0]


def stored_of(bits, signed, shape):
    lo, hi = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
    v = rng.integers(lo, hi + 1, size=shape, dtype=np.int64)
    v.flat[0], v.flat[1] = lo, hi  # both ends of the range
    return v


def words(v, alloc, bits, signed, garbage):
    """The stored values as alloc-bit words: two's complement in the low
    bits; garbage: other data in the bits above High Bit."""
    u = v & ((1 << bits) - 1)
    if garbage and bits < alloc:
        u = u | (rng.integers(0, 2, size=v.shape) << (alloc - 1))
    return u.astype(np.uint8 if alloc == 8 else np.uint16)


def dataset(path, series, modality, rows, cols, alloc, bits, signed, ts=ExplicitVRLittleEndian):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2" if modality == "CT" else "1.2.840.10008.5.1.4.1.1.4"
    meta.MediaStorageSOPInstanceUID = uid()
    meta.TransferSyntaxUID = ts
    ds = FileDataset(path, {}, file_meta=meta, preamble=b"\0" * 128)
    ds.is_little_endian = ts != ExplicitVRBigEndian
    ds.is_implicit_VR = ts == ImplicitVRLittleEndian
    ds.SOPClassUID = meta.MediaStorageSOPClassUID
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.StudyInstanceUID = "1.2.826.0.1.3680043.10.1029.0"
    ds.SeriesInstanceUID = series
    ds.Modality = modality
    ds.SeriesDescription = "lanecast test " + modality
    ds.Rows, ds.Columns = rows, cols
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit = alloc, bits, bits - 1
    ds.PixelRepresentation = 1 if signed else 0
    return ds


def expected(name, slices, ps, row, col, spacing, vtype):
    """slices: [(ipp, values[rows, cols])]: the grid NAME.raw; returns its
    sizes and origin."""
    row, col = np.array(row, float), np.array(col, float)
    pts, vals = [], []
    for ipp, v in slices:
        j, i = np.meshgrid(np.arange(v.shape[0]), np.arange(v.shape[1]), indexing="ij")
        p = np.array(ipp, float)[None, None, :] + i[..., None] * ps[1] * row + j[..., None] * ps[0] * col
        pts.append(p.reshape(-1, 3))
        vals.append(v.reshape(-1))
    pts, vals = np.concatenate(pts), np.concatenate(vals)
    origin = pts.min(axis=0)
    idx = np.rint((pts - origin) / np.array(spacing)).astype(int)
    n = idx.max(axis=0) + 1
    grid = np.zeros(n[::-1], dtype=vtype)
    grid[idx[:, 2], idx[:, 1], idx[:, 0]] = vals
    assert grid.size == len(vals), "the slices do not fill the grid"
    grid.astype("<" + np.dtype(vtype).str[1:]).tofile(os.path.join(out, name + ".raw"))
    return n, origin


def ok(name, inp, opt, vtype, n, spacing, origin, warn="-"):
    t = {np.uint8: "uint8", np.uint16: "uint16", np.int16: "int16", np.float32: "float32"}[vtype]
    expect.append("ok %s %s %s %s %d %d %d %.9g %.9g %.9g %.9g %.9g %.9g %s" % (
        name, inp, opt, t, n[0], n[1], n[2], spacing[0], spacing[1], spacing[2], origin[0], origin[1], origin[2], warn))


def fail(name, inp, opt, file, *words):
    expect.append("fail %s %s %s %s %s" % (name, inp, opt, file, "|".join(words)))


def stack(folder, prefix, series, modality, rows, cols, nz, alloc, bits, signed, ps, row, col, ipp0, dz,
          slope=None, intercept=None, garbage=False, shuffle=True, ts=ExplicitVRLittleEndian):
    """nz slices along row x col from ipp0, dz apart, named in a shuffled
    order (and with shuffled Instance Numbers); returns [(ipp, values)]."""
    os.makedirs(os.path.join(out, folder), exist_ok=True)
    normal = np.cross(row, col)
    names = rng.permutation(nz) if shuffle else np.arange(nz)
    slices = []
    for k in range(nz):
        v = stored_of(bits, signed, (rows, cols))
        ipp = [float(x) for x in np.array(ipp0) + k * dz * normal]
        path = os.path.join(out, folder, "%s%03d.dcm" % (prefix, names[k]))
        ds = dataset(path, series, modality, rows, cols, alloc, bits, signed, ts)
        ds.InstanceNumber = int(names[k]) + 1
        ds.PixelSpacing = [ps[0], ps[1]]
        ds.ImageOrientationPatient = list(row) + list(col)
        ds.ImagePositionPatient = ipp
        if slope is not None:
            ds.RescaleSlope, ds.RescaleIntercept = slope, intercept
        w = words(v, alloc, bits, signed, garbage)
        # big endian: pydicom writes the PixelData bytes as given; it must read its own words back
        ds.PixelData = (w.byteswap() if ts == ExplicitVRBigEndian else w).tobytes()
        ds.save_as(path, write_like_original=False)
        if ts == ExplicitVRBigEndian:
            back = pydicom.dcmread(path).pixel_array
            mask = (1 << alloc) - 1
            assert np.array_equal(back.astype(np.int64) & mask, w.astype(np.int64)), "pydicom reads other words back"
        scaled = v * (1 if slope is None else float(slope)) + (0 if intercept is None else float(intercept))
        slices.append((ipp, scaled))
    return slices


X, Y, Z, NZ = [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, -1]

# CT: 12 bits stored in 16 with other data above them, slope 1, intercept
# -1024 (Hounsfield units) -> int16; files named out of order.
ct = stack("ct", "im", uid(), "CT", 20, 24, 12, 16, 12, False, (0.8, 0.6), X, Y, (-10.0, 5.0, -30.0), 2.5, "1", "-1024",
           garbage=True)
n, o = expected("ct", ct, (0.8, 0.6), X, Y, (0.6, 0.8, 2.5), np.int16)
ok("ct", "ct", "-", np.int16, n, (0.6, 0.8, 2.5), o)
ok("ct_file", "ct/im000.dcm", "-", np.int16, n, (0.6, 0.8, 2.5), o)  # one file: its series in its folder
some = sorted(os.listdir(os.path.join(out, "ct")))[3:9]
sub = expected("ct_list", [ct[k] for k in range(3, 9)], (0.8, 0.6), X, Y, (0.6, 0.8, 2.5), np.int16)
# the files of slices 3..8, given by name in reverse name order
names3 = []
for k in range(3, 9):
    ipp = ct[k][0]
    for f in os.listdir(os.path.join(out, "ct")):
        if list(pydicom.dcmread(os.path.join(out, "ct", f)).ImagePositionPatient) == ipp:
            names3.append("ct/" + f)
ok("ct_list", ":".join(sorted(names3, reverse=True)), "-", np.int16, sub[0], (0.6, 0.8, 2.5), sub[1])

# Two series in one folder: MR uint16 (all 16 bits, no rescale) and a
# signed CT with slope 0.5, intercept -10 (float32).
sa, sb = uid(), uid()
a = stack("two", "a", sa, "MR", 10, 9, 7, 16, 16, False, (1.0, 1.25), X, Y, (0.0, 0.0, 0.0), 3.0)
b = stack("two", "b", sb, "CT", 8, 11, 5, 16, 16, True, (0.5, 0.5), X, Y, (4.0, -2.0, 7.5), 1.5, "0.5", "-10")
n, o = expected("two_1", a, (1.0, 1.25), X, Y, (1.25, 1.0, 3.0), np.uint16)
ok("two_1", "two", "series=1", np.uint16, n, (1.25, 1.0, 3.0), o)
n, o = expected("two_uid", b, (0.5, 0.5), X, Y, (0.5, 0.5, 1.5), np.float32)
ok("two_uid", "two", "series=" + sb, np.float32, n, (0.5, 0.5, 1.5), o)
fail("two_none", "two", "-", "two", "2 DICOM series", "--series")
fail("two_bad", "two", "series=3", "two", "series 1 to 2")

# Signed 8-bit (int16 voxels), implicit VR; unsigned 8-bit.
s8 = stack("s8", "s", uid(), "MR", 9, 10, 6, 8, 8, True, (2.0, 2.0), X, Y, (1.0, 2.0, 3.0), 2.0,
           ts=ImplicitVRLittleEndian)
n, o = expected("s8", s8, (2.0, 2.0), X, Y, (2.0, 2.0, 2.0), np.int16)
ok("s8", "s8", "-", np.int16, n, (2.0, 2.0, 2.0), o)
u8 = stack("u8", "u", uid(), "MR", 7, 6, 4, 8, 8, False, (1.0, 1.0), X, Y, (0.0, 0.0, 0.0), 1.0)
n, o = expected("u8", u8, (1.0, 1.0), X, Y, (1.0, 1.0, 1.0), np.uint8)
ok("u8", "u8", "-", np.uint8, n, (1.0, 1.0, 1.0), o)

# Sagittal, signed 12 bits in 16 (upper bits clear: sign extension is the
# reader's): row direction +y, column direction -z, normal -x.
sag = stack("sag", "sg", uid(), "MR", 12, 14, 5, 16, 12, True, (0.9, 0.7), Y, NZ, (20.0, -5.0, 40.0), 1.1)
n, o = expected("sag", sag, (0.9, 0.7), Y, NZ, (1.1, 0.7, 0.9), np.int16)
ok("sag", "sag", "-", np.int16, n, (1.1, 0.7, 0.9), o)

# Explicit VR Big Endian (1.2.840.10008.1.2.2, retired), 16-bit signed with a
# rescale and 8-bit: the values must be the writer's.
be = stack("be", "be", uid(), "CT", 6, 7, 4, 16, 12, True, (1.0, 1.25), X, Y, (0.0, 1.0, 2.0), 2.0, "1", "-1024",
           ts=ExplicitVRBigEndian)
n, o = expected("be", be, (1.0, 1.25), X, Y, (1.25, 1.0, 2.0), np.int16)
ok("be", "be", "-", np.int16, n, (1.25, 1.0, 2.0), o)
be8 = stack("be8", "b", uid(), "MR", 5, 6, 3, 8, 8, False, (1.0, 1.0), X, Y, (0.0, 0.0, 0.0), 1.0,
            ts=ExplicitVRBigEndian)
n, o = expected("be8", be8, (1.0, 1.0), X, Y, (1.0, 1.0, 1.0), np.uint8)
ok("be8", "be8", "-", np.uint8, n, (1.0, 1.0, 1.0), o)

# Oblique (10 degrees about z): nearest frame, a warning.
c, s_ = np.cos(np.radians(10)), np.sin(np.radians(10))
row, col = np.array([c, s_, 0]), np.array([-s_, c, 0])
stack("obl", "ob", uid(), "CT", 6, 8, 4, 16, 16, True, (1.0, 1.0), list(row), list(col), (0, 0, 0), 2.0)
# the nearest frame keeps the voxel sizes and the volume's centre
centre = 0.5 * (7 * 1.0 * row + 5 * 1.0 * col + 3 * 2.0 * np.cross(row, col))
ok("obl", "obl", "-", np.int16, (8, 6, 4), (1.0, 1.0, 2.0), centre - 0.5 * np.array([7.0, 5.0, 6.0]), "oblique")


def enhanced(name, modality, rows, cols, alloc, bits, signed, ipps, ps, thickness, per=None, shared=None, frames=None):
    """An enhanced multi-frame file NAME.dcm, frame f at ipps[f] (axial),
    rescaled by per[f] = (slope, intercept) in its per-frame functional
    groups, or by shared in the shared ones; frames: a Number of Frames
    other than len(ipps) (a lying header). Returns [(ipp, rescaled values)]."""
    path = os.path.join(out, name + ".dcm")
    ds = dataset(path, uid(), modality, rows, cols, alloc, bits, signed)
    ds.file_meta.MediaStorageSOPClassUID = ds.SOPClassUID = (
        "1.2.840.10008.5.1.4.1.1.2.1" if modality == "CT" else "1.2.840.10008.5.1.4.1.1.4.1")
    ds.NumberOfFrames = len(ipps) if frames is None else frames
    sh, pm, po = Dataset(), Dataset(), Dataset()
    pm.PixelSpacing = [ps[0], ps[1]]
    pm.SliceThickness = thickness
    po.ImageOrientationPatient = X + Y
    sh.PixelMeasuresSequence = Sequence([pm])
    sh.PlaneOrientationSequence = Sequence([po])
    if shared is not None:
        vt = Dataset()
        vt.RescaleSlope, vt.RescaleIntercept, vt.RescaleType = shared[0], shared[1], "US"
        sh.PixelValueTransformationSequence = Sequence([vt])
    ds.SharedFunctionalGroupsSequence = Sequence([sh])
    items, slices, pixels = [], [], []
    for f, ipp in enumerate(ipps):
        item, pp = Dataset(), Dataset()
        pp.ImagePositionPatient = list(ipp)
        item.PlanePositionSequence = Sequence([pp])
        scale = shared if shared is not None else (1, 0)
        if per is not None and per[f] is not None:
            vt = Dataset()
            vt.RescaleSlope, vt.RescaleIntercept, vt.RescaleType = per[f][0], per[f][1], "US"
            item.PixelValueTransformationSequence = Sequence([vt])
            scale = per[f]
        items.append(item)
        v = stored_of(bits, signed, (rows, cols))
        pixels.append(words(v, alloc, bits, signed, False).tobytes())
        slices.append((list(ipp), v * float(scale[0]) + float(scale[1])))
    ds.PerFrameFunctionalGroupsSequence = Sequence(items)
    ds.PixelData = b"".join(pixels)
    ds.save_as(path, write_like_original=False)
    return slices


# Multi-frame (Enhanced MR): 8-bit, per-frame positions stored top down.
frames = enhanced("mf", "MR", 12, 16, 8, 8, False, [(-3.0, 4.0, 10.0 - 3.0 * f) for f in range(5)], (0.75, 0.5), 3.0)
n, o = expected("mf", frames, (0.75, 0.5), X, Y, (0.5, 0.75, 3.0), np.uint8)
ok("mf", "mf.dcm", "-", np.uint8, n, (0.5, 0.75, 3.0), o)

# Enhanced CT with a rescale per frame (Pixel Value Transformation in the
# per-frame functional groups) and frames stored out of position order:
# each frame keeps its own slope and intercept; non-integer ones make
# float32 (as a series of files whose rescales differ); slopes and
# intercepts exact in binary, so the float32 values are the writer's.
order = [3, 0, 5, 1, 4, 2]
ipps = [(2.0, -1.0, -20.0 + 1.5 * k) for k in order]
per = [(0.5, -1024), (1, -1000.5), (1.5, -1024), (2, -999.25), (0.25, -1024), (1, -1030)]
frames = enhanced("mf_ct", "CT", 10, 14, 16, 12, True, ipps, (0.6, 0.7), 1.5, per=per)
n, o = expected("mf_ct", frames, (0.6, 0.7), X, Y, (0.7, 0.6, 1.5), np.float32)
ok("mf_ct", "mf_ct.dcm", "-", np.float32, n, (0.7, 0.6, 1.5), o)
# integer rescales that differ per frame: int16 when every value fits (as a series)
per = [(1, -1024), (1, -1000), (2, -1024), (1, -980), (1, -1010), (3, -2000)]
frames = enhanced("mf_ct_int", "CT", 9, 8, 16, 10, False, ipps, (0.6, 0.7), 1.5, per=per)
n, o = expected("mf_ct_int", frames, (0.6, 0.7), X, Y, (0.7, 0.6, 1.5), np.int16)
ok("mf_ct_int", "mf_ct_int.dcm", "-", np.int16, n, (0.7, 0.6, 1.5), o)
# one rescale for every frame, in the shared functional groups
frames = enhanced("mf_shared", "CT", 9, 8, 16, 12, False, ipps, (0.6, 0.7), 1.5, shared=(2, -100))
n, o = expected("mf_shared", frames, (0.6, 0.7), X, Y, (0.7, 0.6, 1.5), np.int16)
ok("mf_shared", "mf_shared.dcm", "-", np.int16, n, (0.7, 0.6, 1.5), o)
# a rescale for 5 of the 6 frames
enhanced("mf_part", "CT", 9, 8, 16, 12, False, ipps, (0.6, 0.7), 1.5, per=[(1, -1024)] * 5 + [None])
fail("mf_part", "mf_part.dcm", "-", "mf_part.dcm", "(0028,9145) Pixel Value Transformation Sequence",
     "5 of 6 frames")
# a Number of Frames the pixel data cannot hold (7 declared, 6 stored): refused before GDCM sizes its buffer
enhanced("mf_lying", "CT", 9, 8, 16, 12, False, ipps + [(2.0, -1.0, -11.0)], (0.6, 0.7), 1.5, frames=7)
d = pydicom.dcmread(os.path.join(out, "mf_lying.dcm"))  # the per-frame groups say 7 too; cut one frame's pixels
d.PixelData = d.PixelData[: 6 * 9 * 8 * 2]
d.DataSetTrailingPadding = b"\0" * 400  # the file is long enough: the element's own length must be the check
d.save_as(os.path.join(out, "mf_lying.dcm"))
fail("mf_lying", "mf_lying.dcm", "-", "mf_lying.dcm", "element (7FE0,0010) Pixel Data at byte", "holds 864 bytes",
     "(0028,0008) Number of Frames 7 x (0028,0010) Rows 9 x (0028,0011) Columns 8 x 2 bytes", "need 1008")

# A transfer syntax GDCM does not decode (MPEG-2 video), encapsulated.
path = os.path.join(out, "mpeg.dcm")
ds = dataset(path, uid(), "XA", 8, 8, 8, 8, False, "1.2.840.10008.1.2.4.100")
ds.NumberOfFrames = 2
ds.ImagePositionPatient, ds.ImageOrientationPatient, ds.PixelSpacing = [0, 0, 0], X + Y, [1, 1]
ds.SpacingBetweenSlices = 1
ds.PixelData = pydicom.encaps.encapsulate([b"\0\0\1\xb3" + b"\0" * 60])
ds["PixelData"].is_undefined_length = True
ds["PixelData"].VR = "OB"
ds.save_as(path, write_like_original=False)
fail("mpeg", "mpeg.dcm", "-", "mpeg.dcm", "1.2.840.10008.1.2.4.100", "transfer syntax")

# Compressed syntaxes GDCM decodes: the CT series through gdcmconv.
gdcmconv = shutil.which("gdcmconv")
if gdcmconv:
    n, o = expected("ct", ct, (0.8, 0.6), X, Y, (0.6, 0.8, 2.5), np.int16)
    for flag, name in (("--rle", "ct_rle"), ("--jpegls", "ct_jpegls"), ("--jpeg", "ct_jpeg"), ("--j2k", "ct_j2k")):
        os.makedirs(os.path.join(out, name))
        for f in os.listdir(os.path.join(out, "ct")):
            subprocess.run([gdcmconv, flag, os.path.join(out, "ct", f), os.path.join(out, name, f)], check=True)
            if not os.path.exists(os.path.join(out, name, f)):
                sys.exit("dicom_write.py: gdcmconv %s wrote nothing for %s" % (flag, f))
        shutil.copy(os.path.join(out, "ct.raw"), os.path.join(out, name + ".raw"))
        ok(name, name, "-", np.int16, n, (0.6, 0.8, 2.5), o)
else:
    print("dicom_write.py: no gdcmconv (Debian libgdcm-tools): the compressed cases are left out")


# A JPEG file of the series whose fragment holds a start-of-image marker and
# no frame header: GDCM's codec aborts on it (an assertion), in lanecast's
# guard process; the message names that file, not the first of its batch.
if gdcmconv:
    shutil.copytree(os.path.join(out, "ct_jpeg"), os.path.join(out, "jpeg_bad"))
    bad = sorted(os.listdir(os.path.join(out, "jpeg_bad")))[5]
    d = pydicom.dcmread(os.path.join(out, "jpeg_bad", bad))
    d.PixelData = pydicom.encaps.encapsulate([b"\xff\xd8" + b"\0" * 62])
    d["PixelData"].is_undefined_length = True
    d.save_as(os.path.join(out, "jpeg_bad", bad))
    fail("jpeg_bad", "jpeg_bad", "-", "jpeg_bad/" + bad, "GDCM crashed decoding the pixel data", "signal 6")


# Malformed variants of the CT series, each failing with the file named.
def variant(name):
    shutil.copytree(os.path.join(out, "ct"), os.path.join(out, name))
    return sorted(os.listdir(os.path.join(out, name)))


files = variant("trunc")
p = os.path.join(out, "trunc", files[4])
size = os.path.getsize(p)
with open(p, "r+b") as f:
    f.truncate(size - 300)
# the element walk before GDCM (host/formats/dicom_walk.c) names the pixel data element whose length
# runs past the cut
fail("trunc", "trunc", "-", "trunc/" + files[4], "element (7FE0,0010) at byte", "runs past the end of the file")
if gdcmconv:  # a cut compressed file
    shutil.copytree(os.path.join(out, "ct_rle"), os.path.join(out, "trunc_rle"))
    p = os.path.join(out, "trunc_rle", files[4])
    with open(p, "r+b") as f:
        f.truncate(os.path.getsize(p) - 200)
    fail("trunc_rle", "trunc_rle", "-", "trunc_rle/" + files[4], "element (FFFE,E000) at byte", "runs past the end")

files = variant("sizes")
p = os.path.join(out, "sizes", files[2])
d = pydicom.dcmread(p)
d.Columns = 22
d.PixelData = d.PixelData[: 20 * 22 * 2]
d.save_as(p)
fail("sizes", "sizes", "-", "sizes/" + files[2], "22 x 20", "24 x 20")

files = variant("nopos")
p = os.path.join(out, "nopos", files[7])
d = pydicom.dcmread(p)
del d.ImagePositionPatient
d.save_as(p)
fail("nopos", "nopos", "-", "nopos/" + files[7], "Image Position (Patient)")

files = variant("gap")  # a missing slice: one spacing of 5 mm among 2.5
around = []
for f in files:
    ipp = list(pydicom.dcmread(os.path.join(out, "gap", f)).ImagePositionPatient)
    if ipp == ct[5][0]:
        os.remove(os.path.join(out, "gap", f))
    if ipp in (ct[4][0], ct[6][0]):
        around.append((ipp[2], f))
around.sort()
fail("gap", "gap", "-", "gap", "uneven slice spacing", "5 mm between %s/gap/%s and %s/gap/%s" % (
    out, around[0][1], out, around[1][1]), "2.5 mm x 9", "5 mm x 1")

files = variant("dup")
for f in files:
    d = pydicom.dcmread(os.path.join(out, "dup", f))
    if list(d.ImagePositionPatient) == ct[6][0]:
        d.ImagePositionPatient = ct[7][0]
        d.save_as(os.path.join(out, "dup", f))
fail("dup", "dup", "-", "dup", "same position")

with open(os.path.join(out, "expect.txt"), "w") as f:
    f.write("\n".join(expect) + "\n")
print("dicom_write.py: %d cases in %s" % (len(expect), out))
