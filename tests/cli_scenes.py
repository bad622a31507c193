"""Small scenes the CLI tests render, written into the folder given:
ball.raw (a 16^3 float32 ball, 1 - distance from the centre / 7.5),
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
with open(d + "/atoms.xyz", "w") as f:
    f.write("C 0 0 0\nO 1.2 0 0\nC 0 1.3 0.4\n")
with open(d + "/set.rbf", "w") as f:
    f.write("lanecast-rbf 1\nbias 0\ncount 2\n0 0 0 0.8 1\n1 0 0 0.5 -0.5\n")
