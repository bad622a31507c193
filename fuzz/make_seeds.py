#!/usr/bin/env python3
"""Seed corpora for the fuzz harnesses (fuzz/fuzz_load.c, fuzz/fuzz_tf.c).

usage: make_seeds.py OUT_DIR [DATA_DIR]

Writes OUT_DIR/<harness>/<name> files: small hand-made inputs of every
flavour each reader takes, and, when DATA_DIR (the shared data, e.g.
../shared/data) exists, small inputs cut from its real files (the first
atoms of the PDB, GRO and PSF files, the NRRD and MetaImage headers with
tiny attached volumes, the GADGET headers with a few particles). Nothing is
copied whole: seeds stay small so that each execution is fast. Input
layouts (see fuzz/fuzz_load.c): raw formats and HDF5 take a first line of
key=value options; DCD takes a first line with the PSF's length, the PSF,
then the DCD."""
import gzip
import os
import struct
import sys

out = sys.argv[1]
data = sys.argv[2] if len(sys.argv) > 2 else ""
have_data = bool(data) and os.path.isdir(data)


def put(h, name, b):
    os.makedirs(os.path.join(out, h), exist_ok=True)
    if isinstance(b, str):
        b = b.encode()
    with open(os.path.join(out, h, name), "wb") as f:
        f.write(b)


def rec(b):
    """A Fortran unformatted record: length, bytes, length."""
    return struct.pack("<i", len(b)) + b + struct.pack("<i", len(b))


# ---- particles, text
put("xyz", "bare", "C 0 0 0\nO 1.2 0 0\nH 0 1 0\n")
put("xyz", "frames", "3\nframe 0\nC 0 0 0\nO 1.2 0 0\nH 0 1 0\n3\nframe 1\nC 0 0 1\nO 1.2 0 1\nH 0 1 1\n")
put("xyz", "extxyz", '2\nLattice="5 0 0 0 5 0 0 0 5" Properties=species:S:1:pos:R:3:radius:R:1:charge:R:1\n'
    "Na 0 0 0 1.1 1\nCl 2.8 0 0 1.7 -1\n")
put("pdb", "atoms", "ATOM      1  N   MET A   1      27.340  24.430   2.614  1.00  9.67           N\n"
    "ATOM      2  CA  MET A   1      26.266  25.413   2.842  1.00 10.38           C\n"
    "HETATM    3 ZN    ZN A 101      20.000  20.000  20.000  1.00 10.00          ZN\n"
    "END\n")
put("pdb", "models", "MODEL        1\nATOM      1  CA  GLY A   1       0.000   0.000   0.000  1.00  0.00           C\n"
    "ENDMDL\nMODEL        2\nATOM      1  CA  GLY A   1       1.000   0.000   0.000  1.00  0.00           C\nENDMDL\nEND\n")
put("gro", "water", "water\n    3\n    1SOL     OW    1   0.126   1.624   1.679\n"
    "    1SOL    HW1    2   0.190   1.661   1.747\n    1SOL    HW2    3   0.177   1.568   1.613\n"
    "   1.86206   1.86206   1.86206\n")
put("mmcif", "atoms", "data_test\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n"
    "_atom_site.label_atom_id\n_atom_site.label_alt_id\n_atom_site.label_comp_id\n_atom_site.Cartn_x\n"
    "_atom_site.Cartn_y\n_atom_site.Cartn_z\n_atom_site.pdbx_PDB_model_num\n"
    "ATOM 1 N N . MET 27.340 24.430 2.614 1\nATOM 2 C CA A MET 26.266 25.413 2.842 1\n"
    "ATOM 3 C CA B MET 26.300 25.400 2.800 1\nHETATM 4 O O . HOH 'x' 1 2 3 1\n#\n")
put("csv", "radius", "x,y,z,radius,value,type\n0,0,0,1,2,0\n1,0,0,0.5,1,1\n0,1,0,0.7,3,0\n")
put("csv", "knn", "# positions only\nx\ty\tz\tmass\n0\t0\t0\t1\n1\t0\t0\t1\n0\t1\t0\t2\n0\t0\t1\t1\n")
put("lammps", "ortho", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS pp pp pp\n0 10\n0 10\n0 10\n"
    "ITEM: ATOMS id type x y z q\n1 1 1 1 1 0.5\n2 2 2 2 2 -0.5\n3 1 3 3 3 0\n")
put("lammps", "scaled_triclinic", "ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n2\n"
    "ITEM: BOX BOUNDS xy xz yz pp pp pp\n0 10 1\n0 10 0\n0 10 0\nITEM: ATOMS id type xs ys zs\n"
    "1 1 0.1 0.1 0.1\n2 1 0.5 0.5 0.5\nITEM: TIMESTEP\n6\nITEM: NUMBER OF ATOMS\n1\n"
    "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\nITEM: ATOMS id type x y z\n1 1 0.5 0.5 0.5\n")


def gadget(npart, mass, pos, ids, boxsize=10.0, u=None, masses=None):
    h = struct.pack("<6i", *npart) + struct.pack("<6d", *mass) + struct.pack("<2d", 0.0, 0.0)
    h += struct.pack("<2i", 0, 0) + struct.pack("<6I", *npart) + struct.pack("<2i", 0, 1)
    h += struct.pack("<4d", boxsize, 0.3, 0.7, 0.7)
    h += b"\0" * (256 - len(h))
    n = sum(npart)
    b = rec(h) + rec(struct.pack("<%df" % (3 * n), *pos)) + rec(struct.pack("<%df" % (3 * n), *([0.0] * 3 * n)))
    b += rec(struct.pack("<%dI" % n, *ids))
    if masses:
        b += rec(struct.pack("<%df" % len(masses), *masses))
    if u:
        b += rec(struct.pack("<%df" % len(u), *u))
    return b


put("gadget", "gas_halo", gadget([2, 3, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0],
                                 [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1], [1, 2, 3, 4, 5],
                                 u=[1.0, 2.0], masses=[0.5, 0.25]))
put("gadget", "halo", gadget([0, 4, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [float(i) for i in range(12)], [1, 2, 3, 4]))

# ---- DCD + PSF
psf = ("PSF\n\n       1 !NTITLE\n* fuzz seed\n\n       3 !NATOM\n"
       "       1 A    1    MET  N      56  -0.300000       14.0070           0\n"
       "       2 A    1    MET  CA     22   0.210000       12.0110           0\n"
       "       3 A    1    MET  O      70  -0.510000       15.9990           0\n\n"
       "       0 !NBOND: bonds\n\n")


def dcd(natom, nframes, cell):
    ic = [0] * 20
    ic[0], ic[10], ic[19] = nframes, cell, 24
    b = rec(b"CORD" + struct.pack("<20i", *ic)) + rec(struct.pack("<i", 1) + b"* fuzz".ljust(80))
    b += rec(struct.pack("<i", natom))
    for k in range(nframes):
        if cell:
            b += rec(struct.pack("<6d", 10, 90, 10, 90, 90, 10))
        for c in range(3):
            b += rec(struct.pack("<%df" % natom, *[float(i + k + c) for i in range(natom)]))
    return b


def companion(first, second):
    first = first.encode() if isinstance(first, str) else first
    return str(len(first)).encode() + b"\n" + first + second


put("dcd_psf", "cell2", companion(psf, dcd(3, 2, 1)))
put("dcd_psf", "nocell", companion(psf, dcd(3, 1, 0)))
put("dcd_psf", "no_topology", companion(b"", dcd(3, 1, 0)))

# ---- GROMACS XTC/TRR: the first frame of each file of tests/data/traj (written
# by MDAnalysis and GROMACS; README.md there), and a .gro/.pdb/.psf topology
TRAJ = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "traj")


def first_frames(name, count=1):
    """The first `count` frames of an XTC or TRR file, by their headers."""
    with open(os.path.join(TRAJ, name), "rb") as f:
        b = f.read()
    off = 0
    for _ in range(count):
        if name.endswith(".xtc"):
            n = struct.unpack_from(">i", b, off + 4)[0]
            off += 56 + 12 * n if n <= 9 else 92 + (struct.unpack_from(">i", b, off + 88)[0] + 3) // 4 * 4
        else:
            sizes = struct.unpack_from(">13i", b, off + 24)
            real = sizes[2] // 9 if sizes[2] else sizes[7] // (3 * sizes[10])
            off += 76 + 2 * real + sum(sizes[:10])
    return b[:off]


if os.path.isdir(TRAJ):
    for name in ("small.xtc", "adk_ca.xtc", "wide.xtc", "gmx_ca.xtc"):
        put("xtc", name, first_frames(name, 2 if name == "small.xtc" else 1))
    for name in ("adk_ca.trr", "gmx_ca_d.trr"):
        put("trr", name, first_frames(name))
    small = first_frames("small.xtc")
    gro = "seven\n    7\n" + "".join("    1MET     %-3s%5d   0.100   0.200   0.300\n" % (a, i + 1) for i, a in
                                       enumerate(["N", "HT1", "HT2", "HT3", "CA", "HA", "CB"])) + "   1.0 1.0 1.0\n"
    put("xtc_top", "gro", companion(gro.encode(), small))
    pdb = "".join("ATOM  %5d  %-3s MET A   1       0.000   0.000   0.000  1.00  0.00           %s\n" % (i + 1, a, a[0])
                  for i, a in enumerate(["N", "HT1", "HT2", "HT3", "CA", "HA", "CB"])) + "END\n"
    put("xtc_top", "pdb", companion(pdb.encode(), small))
    put("xtc_top", "none", companion(b"", small))
    for name in ("adk_ca.ncdf", "restart.ncrst"):
        with open(os.path.join(TRAJ, name), "rb") as f:
            put("ncdf", name, f.read())

# ---- raw
put("raw_particles", "four", b"count=4 radius=0.5\n" + struct.pack("<12f", *[float(i) for i in range(12)]))
put("raw_volume", "u8", b"size=4,4,2 type=uint8\n" + bytes(range(32)))
put("raw_volume", "u16_be", b"size=2,2,2 type=uint16 endian=big spacing=1,2,3\n" + bytes(range(16)))
put("raw_volume", "f32", b"size=2,2,2 type=float32 origin=1,1,1\n" + struct.pack("<8f", *[0.5 * i for i in range(8)]))
put("raw_volume", "i16", b"size=2,3,2 type=int16\n" + struct.pack("<12h", *range(-6, 6)))

# ---- volumes with headers
vox = bytes((7 * i) % 256 for i in range(27))
put("nrrd", "attached_u8", b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 3 3\nspacings: 1 1 2\n"
    b"encoding: raw\n\n" + vox)
put("nrrd", "attached_f32_space", b"NRRD0005\ntype: float\ndimension: 3\nsizes: 2 2 2\n"
    b"space directions: (1,0,0) (0,2,0) (0,0,1)\nspace origin: (0,0,0)\nendian: big\nencoding: raw\n\n"
    + struct.pack(">8f", *range(8)))
put("nrrd", "attached_gzip", b"NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\nendian: little\n"
    b"byte skip: 0\n\n" + gzip.compress(struct.pack("<8h", *range(-4, 4))))
put("nrrd", "ascii", b"NRRD0004\ntype: ushort\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n\n1 2 3 4 5 6 7 8\n")
put("metaimage", "local_u8", b"ObjectType = Image\nNDims = 3\nDimSize = 3 3 3\nElementSpacing = 1 1 1\n"
    b"ElementType = MET_UCHAR\nElementDataFile = LOCAL\n" + vox)
put("metaimage", "local_f32_msb", b"NDims = 3\nDimSize = 2 2 2\nOffset = 1 2 3\nElementType = MET_FLOAT\n"
    b"ElementByteOrderMSB = True\nHeaderSize = 0\nElementDataFile = LOCAL\n" + struct.pack(">8f", *range(8)))
put("metaimage", "compressed", b"NDims = 3\nDimSize = 2 2 2\nElementType = MET_USHORT\nCompressedData = True\n"
    b"ElementDataFile = LOCAL\n" + gzip.compress(struct.pack("<8H", *range(8))))


def nifti1(dims, dtype, bitpix, payload, scl=(0.0, 0.0)):
    h = struct.pack("<i", 348) + b"\0" * 36 + struct.pack("<8h", 3, *dims, 1, 1, 1, 1)
    h += struct.pack("<3f", 0, 0, 0) + struct.pack("<hhhh", 0, dtype, bitpix, 0)
    h += struct.pack("<8f", 1, 1, 1, 1, 1, 1, 1, 1) + struct.pack("<f", 352.0) + struct.pack("<2f", *scl)
    h += b"\0" * (348 - len(h))
    h = bytearray(h)
    h[123] = 10  # xyzt_units: mm, s
    h[344:348] = b"n+1\0"
    return bytes(h) + b"\0\0\0\0" + payload


put("nifti", "u8", nifti1((3, 3, 3), 2, 8, vox))
put("nifti", "f32_scaled", nifti1((2, 2, 2), 16, 32, struct.pack("<8f", *range(8)), (2.0, 1.0)))
put("vtk", "ascii", "# vtk DataFile Version 3.0\nfuzz\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n"
    "ORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA 8\nSCALARS density float 1\nLOOKUP_TABLE default\n"
    "0 1 2 3 4 5 6 7\n")
put("vtk", "binary", b"# vtk DataFile Version 2.0\nfuzz\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n"
    b"ASPECT_RATIO 1 1 1\nORIGIN 0 0 0\nPOINT_DATA 8\nSCALARS v unsigned_short\nLOOKUP_TABLE default\n"
    + struct.pack(">8H", *range(8)) + b"\nFIELD f 1\nw 1 8 float\n" + struct.pack(">8f", *range(8)))

# ---- DICOM: multi-frame Part 10 files (a file alone is a volume), explicit
# VR little endian (or big endian, retired), written element by element
# (PS3.5 7.1.2, PS3.10 7.1)
def dcm_el(group, elem, vr, value, big=False):
    if isinstance(value, str):
        value = value.encode()
    if len(value) % 2:
        value += b"\0" if vr in ("UI", "OB") else b" "
    e = ">" if big else "<"
    head = struct.pack(e + "HH", group, elem) + vr.encode()
    if vr in ("OB", "OW", "SQ", "UN", "UT"):
        return head + struct.pack(e + "HI", 0, len(value)) + value
    return head + struct.pack(e + "H", len(value)) + value


def dcm_items(items, big=False):
    """A sequence's or encapsulated pixel data's items (defined lengths)."""
    return b"".join(struct.pack(">HHI" if big else "<HHI", 0xFFFE, 0xE000, len(i)) + i for i in items)


def dicom(rows, cols, frames, bits, signed, pixels, extra=(), ts="1.2.840.10008.1.2.1", fragments=None):
    """pixels: the native words (in the syntax's byte order), or with
    fragments (a list of byte strings) encapsulated pixel data after an
    empty Basic Offset Table."""
    big = ts == "1.2.840.10008.1.2.2"
    meta = dcm_el(2, 1, "OB", b"\0\1") + dcm_el(2, 2, "UI", "1.2.840.10008.5.1.4.1.1.4") + \
        dcm_el(2, 3, "UI", "1.2.3.4") + dcm_el(2, 0x10, "UI", ts)
    meta = dcm_el(2, 0, "UL", struct.pack("<I", len(meta))) + meta
    us = ">H" if big else "<H"
    els = [(0x0008, 0x0060, "CS", "MR"), (0x0018, 0x0088, "DS", "2.5"), (0x0020, 0x000E, "UI", "1.2.3.5"),
           (0x0020, 0x0032, "DS", "-1\\2.5\\3"), (0x0020, 0x0037, "DS", "1\\0\\0\\0\\1\\0"),
           (0x0028, 0x0002, "US", struct.pack(us, 1)), (0x0028, 0x0004, "CS", "MONOCHROME2"),
           (0x0028, 0x0008, "IS", str(frames)), (0x0028, 0x0010, "US", struct.pack(us, rows)),
           (0x0028, 0x0011, "US", struct.pack(us, cols)), (0x0028, 0x0030, "DS", "0.5\\0.75"),
           (0x0028, 0x0100, "US", struct.pack(us, bits)), (0x0028, 0x0101, "US", struct.pack(us, bits)),
           (0x0028, 0x0102, "US", struct.pack(us, bits - 1)), (0x0028, 0x0103, "US", struct.pack(us, signed))]
    els += list(extra)
    body = b"".join(dcm_el(*e, big=big) for e in sorted(els))
    if fragments is None:
        pix = dcm_el(0x7FE0, 0x0010, "OB" if bits == 8 else "OW", pixels, big)
    else:
        pix = struct.pack("<HH", 0x7FE0, 0x10) + b"OB" + struct.pack("<HI", 0, 0xFFFFFFFF) + \
            dcm_items([b""] + fragments) + struct.pack("<HHI", 0xFFFE, 0xE0DD, 0)
    return b"\0" * 128 + b"DICM" + meta + body + pix


def rle_frame(b):
    """One 8-bit frame in DICOM RLE (PS3.5 G): a 64-byte header naming one
    segment, then PackBits literal runs of at most 128 bytes."""
    seg = b"".join(bytes([len(b[i:i + 128]) - 1]) + b[i:i + 128] for i in range(0, len(b), 128))
    seg += b"\x80" * (len(seg) % 2)  # -128: PackBits' no-op, to an even length
    return struct.pack("<16I", 1, 64, *([0] * 14)) + seg


put("dicom", "u8_frames", dicom(3, 4, 2, 8, 0, bytes(range(24))))
put("dicom", "s16_rescaled", dicom(2, 3, 3, 16, 1, struct.pack("<18h", *range(-9, 9)),
                                   [(0x0028, 0x1052, "DS", "-1024"), (0x0028, 0x1053, "DS", "0.5")]))
put("dicom", "offsets", dicom(2, 2, 3, 16, 0, struct.pack("<12H", *range(12)),
                              [(0x3004, 0x000C, "DS", "0\\3\\1.5")]))
put("dicom", "big_endian", dicom(2, 3, 2, 16, 1, struct.pack(">12h", *range(-6, 6)), ts="1.2.840.10008.1.2.2"))
put("dicom", "rle", dicom(3, 4, 2, 8, 0, None, ts="1.2.840.10008.1.2.5",
                          fragments=[rle_frame(bytes(range(12))), rle_frame(bytes(range(12, 24)))]))


# Enhanced multi-frame: shared pixel measures and orientation, per frame a
# plane position and a rescale (functional groups, PS3.3 C.7.6.16)
def sq(group, elem, items):
    return (group, elem, "SQ", dcm_items(items))


per = [dcm_el(*sq(0x0020, 0x9113, [dcm_el(0x0020, 0x0032, "DS", "0\\0\\%d" % (3 - 2 * f))])) +
       dcm_el(*sq(0x0028, 0x9145, [dcm_el(0x0028, 0x1052, "DS", str(-10 * f)) + dcm_el(0x0028, 0x1053, "DS", "0.5")]))
       for f in range(3)]
shared = dcm_el(*sq(0x0020, 0x9116, [dcm_el(0x0020, 0x0037, "DS", "1\\0\\0\\0\\1\\0")])) + \
    dcm_el(*sq(0x0028, 0x9110, [dcm_el(0x0028, 0x0030, "DS", "0.5\\0.5")]))
put("dicom", "enhanced", dicom(2, 2, 3, 16, 0, struct.pack("<12H", *range(12)),
                               [sq(0x5200, 0x9229, [shared]), sq(0x5200, 0x9230, per)]))

# ---- RBF sets
put("rbf_text", "two", "lanecast-rbf 1\n# a comment\nbias 0.25\ncount 2\n0 0 0 1 1\n1 0 0 0.5 -1\n")
put("rbf_binary", "two", b"\x89LCRBF\r\n" + struct.pack("<IIQfI", 1, 0, 2, 0.25, 0)
    + struct.pack("<10f", 0, 0, 0, 1, 1, 1, 0, 0, 0.5, -1))

# ---- transfer functions (SPEC.md JSON, fields, ParaView presets)
put("tf", "single", '{"color": [[0, 0, 0, 1], [1, 1, 0, 0]], "opacity": [[0, 0], [1, 2.5]], "range": [0, 10]}')
put("tf", "fields", '{"fields": [{"color": [[0, 1, 1, 1]], "opacity": [[0, 0], [0.5, 1], [1, 3]]},'
    ' {"color": [[0, 0, 1, 0], [1, 0, 0, 1]], "opacity": [[0, 1]]}]}')
put("tf", "paraview", '[{"Name": "Cool to Warm", "ColorSpace": "Diverging", "RGBPoints": [-1, 0.23, 0.3, 0.75, '
    '0, 0.86, 0.86, 0.86, 1, 0.7, 0.015, 0.15], "Points": [-1, 0, 0.5, 0, 1, 0.8, 0.5, 0]}]')

# ---- cut from the shared data
if have_data:
    P = os.path.join(data, "particles")
    V = os.path.join(data, "volumes")
    for name in ("1tii.pdb", "1tw7_solvated.pdb"):
        p = os.path.join(P, name)
        if os.path.exists(p):
            with open(p, "rb") as f:
                lines = f.read().split(b"\n")
            keep = [l for l in lines if not l.startswith((b"ATOM", b"HETATM"))][:20]
            atoms = [l for l in lines if l.startswith((b"ATOM", b"HETATM"))]
            put("pdb", "shared_" + name, b"\n".join(keep[:-1] + atoms[:30] + atoms[-10:] + [b"END", b""]))
            xyz = []
            for l in atoms[:30]:
                el = l[76:78].strip() or l[12:14].strip()
                xyz.append(b"%s %s %s %s" % (el, l[30:38].strip(), l[38:46].strip(), l[46:54].strip()))
            put("xyz", "shared_" + name, b"%d\nfrom %s\n" % (len(xyz), name.encode()) + b"\n".join(xyz) + b"\n")
    p = os.path.join(P, "bigbox_water.gro.gz")
    if os.path.exists(p):
        with gzip.open(p, "rb") as f:
            head = [f.readline() for _ in range(32)]
            last = b""
            for l in f:
                last = l
        put("gro", "shared_bigbox", head[0] + b"%5d\n" % 30 + b"".join(head[2:32]) + last)
    p = os.path.join(P, "adk.psf")
    if os.path.exists(p):
        with open(p, "rb") as f:
            lines = f.read().split(b"\n")
        i = next(k for k, l in enumerate(lines) if b"!NATOM" in l)
        small = b"\n".join(lines[:i] + [b"       5 !NATOM"] + lines[i + 1:i + 6] + [b"", b"       0 !NBOND: bonds", b"", b""])
        put("dcd_psf", "shared_adk", companion(small, dcd(5, 2, 1)))
    for name in ("gadget_galaxy.dat", "gadget_lcdm_gas.dat"):
        p = os.path.join(P, name)
        if os.path.exists(p):
            with open(p, "rb") as f:
                f.read(4)
                hdr = bytearray(f.read(256))
                f.read(4)
                npart = struct.unpack_from("<6i", hdr, 0)
                mass = struct.unpack_from("<6d", hdr, 24)
                n = sum(npart)
                f.read(4)
                pos = struct.unpack("<%df" % (3 * n), f.read(12 * n))
            small = [min(k, 3) for k in npart]
            pick = []
            start = 0
            for t in range(6):
                pick += pos[3 * start:3 * (start + small[t])]
                start += npart[t]
            m = sum(small)
            masses = [1.0] * sum(small[t] for t in range(6) if mass[t] == 0)
            u = [1.0] * small[0] if small[0] else None
            put("gadget", "shared_" + name, gadget(small, mass, pick, list(range(1, m + 1)),
                                                   boxsize=struct.unpack_from("<d", hdr, 96 + 8)[0],
                                                   masses=masses or None, u=u))
    for name in sorted(os.listdir(V)) if os.path.isdir(V) else []:
        p = os.path.join(V, name)
        if name.endswith(".nhdr"):
            with open(p, "rb") as f:
                lines = [l for l in f.read().split(b"\n") if l]
            hdr, tp, gz = [], b"uint8", False
            for l in lines:
                if l.startswith(b"data file"):
                    continue
                if l.startswith(b"sizes"):
                    l = b"sizes: 3 2 2"
                if l.startswith(b"type:"):
                    tp = l.split(b":")[1].strip()
                if l.startswith(b"encoding:"):
                    gz = b"gz" in l
                hdr.append(l)
            size = {b"uint8": 1, b"uchar": 1, b"short": 2, b"ushort": 2, b"uint16": 2, b"float": 4}.get(tp, 1)
            body = bytes((13 * i) % 251 for i in range(12 * size))
            put("nrrd", "shared_" + name, b"\n".join(hdr) + b"\n\n" + (gzip.compress(body) if gz else body))
        if name.endswith(".mhd"):
            with open(p, "rb") as f:
                lines = [l for l in f.read().split(b"\n") if l.strip()]
            hdr = [b"DimSize = 3 2 2" if l.startswith(b"DimSize") else
                   b"ElementDataFile = LOCAL" if l.startswith(b"ElementDataFile") else l for l in lines]
            put("metaimage", "shared_" + name, b"\n".join(hdr) + b"\n" + bytes(range(12)))
print("seeds in %s%s" % (out, " (with cuts of %s)" % data if have_data else " (hand-made only)"))
