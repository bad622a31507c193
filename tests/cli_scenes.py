"""Small scenes the CLI tests render, written into the folder given:
ball.raw (a 16^3 float32 ball, 1 - distance from the centre / 7.5) and the
same voxels behind NRRD (ball.nhdr), MetaImage (ball.mhd), gzip NRRD
(ballz.nhdr, ballz.raw.gz) and NIfTI-1 (ball.nii) headers, half.raw (16^3, zero
where x < 8),
atoms.xyz (three atoms of two elements) and set.rbf (two RBFs of both signs).
usage: python3 cli_scenes.py DIR"""
import math
import struct
import sys

d = sys.argv[1]
with open(d + "/ball.raw", "wb") as f:
    for k in range(16):
        for j in range(16):
            for i in range(16):
                f.write(struct.pack("<f", 1.0 - math.sqrt((i - 7.5) ** 2 + (j - 7.5) ** 2 + (k - 7.5) ** 2) / 7.5))
with open(d + "/ball.raw", "rb") as f:
    ball = f.read()
with open(d + "/ball.nhdr", "w") as f:
    f.write("NRRD0004\ntype: float\ndimension: 3\nsizes: 16 16 16\nendian: little\nencoding: raw\ndata file: ball.raw\n")
with open(d + "/ball.mhd", "w") as f:
    f.write("ObjectType = Image\nNDims = 3\nDimSize = 16 16 16\nElementType = MET_FLOAT\nElementDataFile = ball.raw\n")
import gzip
with gzip.open(d + "/ballz.raw.gz", "wb") as f:
    f.write(ball)
with open(d + "/ballz.nhdr", "w") as f:
    f.write("NRRD0004\ntype: float\ndimension: 3\nsizes: 16 16 16\nendian: little\nencoding: gzip\n"
            "data file: ballz.raw.gz\n")
hdr = bytearray(352)
struct.pack_into("<i", hdr, 0, 348)
struct.pack_into("<8h", hdr, 40, 3, 16, 16, 16, 1, 1, 1, 1)
struct.pack_into("<hh", hdr, 70, 16, 32)  # DT_FLOAT32, bitpix
struct.pack_into("<8f", hdr, 76, 1, 1, 1, 1, 1, 1, 1, 1)
struct.pack_into("<f", hdr, 108, 352.0)
hdr[344:348] = b"n+1\0"
with open(d + "/ball.nii", "wb") as f:
    f.write(bytes(hdr) + ball)
with open(d + "/half.raw", "wb") as f:  # zero where x < 8: its regions' histograms differ
    for k in range(16):
        for j in range(16):
            for i in range(16):
                f.write(struct.pack("<f", 0.0 if i < 8 else (i - 7) / 8.0 + 0.01 * ((i * 7 + j * 3 + k) % 5)))
with open(d + "/atoms.xyz", "w") as f:
    f.write("C 0 0 0\nO 1.2 0 0\nC 0 1.3 0.4\n")
with open(d + "/set.rbf", "w") as f:
    f.write("lanecast-rbf 1\nbias 0\ncount 2\n0 0 0 0.8 1\n1 0 0 0.5 -0.5\n")
