#!/bin/sh
# mpiexec -np K lanecast render of particle files loaded by parts
# (host/mpi/mpi_pload.c): raw float32 files read as each rank's rows, PDB
# and GADGET files with k-nearest radii read by rank 0 and scattered (HDF5
# snapshots with smoothing lengths when h5py can write one, read by shares:
# more in test_cli_mpi_pshare.sh; and --normalise of one, whose float image
# is the one process's byte for byte), and RBF sets (mpi_rload.c: scattered from rank 0),
# each rank keeping its owners and ghosts: the PNG
# rank 0 writes equals the one-process PNG byte for byte (dvr with alpha_stop
# 1 differs from one process by float round-off, far below an 8-bit step).
# Float images (EXR, view_imgcmp exact; with the argument bits, test
# cli_mpi_bits): the parts' BVHs are in the canonical order, as one process's
# by default, so against one process with its defaults mip, iso and slice
# images are the same floats at
# K = 1..4 (a PDB molecule, raw particles, GADGET with k-nearest radii, an
# RBF set; eye inside the data, orthographic), dvr too by the chain (the
# default), by binary swap (--composite swap) within the "over"
# compositing's round-off (2e-5, as for grids); with the canonical order off
# under mpirun (--canonical-order 0) some of three images differ. Without
# bits: an HDF5 SPH snapshot with varying smoothing lengths (iso, K = 2, 4)
# and --normalise (slice, K = 1..3) the same way.
# More ranks than particles; --sigma under mpirun (the ghosts reach as far);
# --stats rows whose region weights sum to the particle count, and whose read
# column names each rank's share (raw) or rank 0's whole read (PDB); a file cut
# short, seen by the last rank only: every rank exits non-zero with its
# message and no image. usage: test_cli_mpi_particles.sh LANECAST MPIEXEC VIEW_IMGCMP [bits]
# (bits: only the float images against one process, test cli_mpi_bits)
set -eu
exe=$1
mpiexec=$2
imgcmp=${3:-}
mode=${4:-}
. "$(dirname "$0")/cli_mpi_run.sh" # $dir, run
python3 - "$dir" <<'PY'
import math, struct, sys
d = sys.argv[1]
seed = [7]
def rnd():
    seed[0] = (seed[0] * 1103515245 + 12345) % 2147483648
    return seed[0] / 2147483648.0
def point():  # clustered towards a corner: kd splits are not the box's halves
    return [2.0 * rnd() * rnd() - 1.0 for _ in range(3)]
with open(d + "/pts.f32", "wb") as f:
    for i in range(3000):
        f.write(struct.pack("<3f", *point()))
with open(d + "/pts.f32", "rb") as f:
    b = f.read()
with open(d + "/short.f32", "wb") as f:
    f.write(b[:-20])
with open(d + "/mol.pdb", "w") as f:
    for i in range(60):
        x, y, z = (6.0 * c for c in point())
        el = "CNO"[i % 3]
        f.write("ATOM  %5d  %-3s ALA A%4d    %8.3f%8.3f%8.3f  1.00 %5.2f          %2s\n" % (i + 1, el, i // 4 + 1, x, y, z, 10 + i % 7, el))
    f.write("END\n")
def rec(b):
    return struct.pack("<i", len(b)) + b + struct.pack("<i", len(b))
n = 800
head = struct.pack("<6i", 0, n, 0, 0, 0, 0) + struct.pack("<6d", 0, 1.0, 0, 0, 0, 0) + struct.pack("<2d", 1.0, 0.0)
head += struct.pack("<2i", 0, 0) + struct.pack("<6I", 0, n, 0, 0, 0, 0) + struct.pack("<2i", 0, 1) + struct.pack("<d", 0.0)
head += b"\0" * (256 - len(head))
pos = b"".join(struct.pack("<3f", *point()) for _ in range(n))
with open(d + "/terms.rbf", "w") as f:
    f.write("lanecast-rbf 1\nbias 0\ncount 200\n")
    for i in range(200):
        x, y, z = point()
        f.write("%.5f %.5f %.5f %.4f %.4f\n" % (x, y, z, 0.04 + 0.08 * rnd(), 2.0 * rnd() - 0.6))
with open(d + "/snap.gadget", "wb") as f:
    f.write(rec(head) + rec(pos) + rec(b"\0" * (12 * n)) + rec(b"".join(struct.pack("<I", i) for i in range(n))))
PY
prun() { # K, name, args...: as run, dvr without early termination
    k=$1 name=$2
    shift 2
    run "$k" "$name" png --alpha-stop 1 "$@"
}
raw="$dir/pts.f32 --raw-particles 3000 --radius 0.05"
P=--canonical-order
inside="--eye 0.1,0.05,0.0 --at 1,0.6,-0.4 --fov 70"
ortho="--eye -6,2,3 --at 0,0,0 --ortho 3"
if [ "$mode" = bits ]; then
    # bit for bit: K = 1..4 against one process with the canonical order
    bits mol-mip "1 2 3 4" "$dir/mol.pdb" --mode mip
    bits raw-iso-inside "1 2 3 4" $raw --mode iso --iso 0.4 $inside
    bits raw-mip-ortho "1 2 3 4" $raw --mode mip $ortho
    bits gadget-m4-slice "1 2 3 4" "$dir/snap.gadget" --kernel m4 --mode slice --plane 0,0,0.1,0.1,0.2,1 $ortho
    bits rbf-iso "1 2 3 4" "$dir/terms.rbf" --mode iso --iso 0.3 $ortho
    bits rbf-slice-inside "2 4" "$dir/terms.rbf" --mode slice --plane 0.1,0,0,1,0.3,0.2 $inside
    # dvr by the chain (the default): the same floats too
    bits raw-dvr "2 3 4" $raw
    bits rbf-dvr-inside "3" "$dir/terms.rbf" $inside
    bits mol-dvr-bands "4" "$dir/mol.pdb" --bands 7 $ortho
    near=0.0051 # dvr by binary swap: within the over's round-off (2e-5)
    bits raw-dvr-swap "2 4" $raw --composite swap
    near=
    # the canonical order off under mpirun: some image of three differs from one process's
    differ=0
    for c in "mip $ortho" "slice --plane 0,0,0.1,0.1,0.2,1" "iso --iso 0.4 $inside"; do
        set -- --size 40x30 $raw --mode $c
        "$exe" render "$@" --threads 1 --quiet -o "$dir/off-one.exr" 2> "$dir/err1" || true
        timeout 60 "$mpiexec" --oversubscribe -np 3 "$exe" render "$@" $P 0 --threads 1 --quiet \
            -o "$dir/off-np3.exr" 2> "$dir/err" || true
        "$imgcmp" "$dir/off-np3.exr" "$dir/off-one.exr" exact > /dev/null 2>&1 || differ=$((differ + 1))
    done
    if [ $differ -gt 0 ]; then
        echo "ok   --canonical-order 0 under mpirun: $differ of 3 float images differ from one process (the check can fail)"
    else
        echo "FAIL --canonical-order 0 under mpirun: every float image equal, the bit-for-bit cases prove nothing"
        fail=1
    fi
    exit $fail
fi

prun 2 raw-dvr $raw
prun 4 raw-mip $raw --mode mip --eye 0.2,0.1,0.3 --at 1,1,1
prun 2 raw-sigma3 $raw --sigma 3 --mode iso --iso 0.4 --shade phong
prun 3 pdb-scattered "$dir/mol.pdb"
prun 2 gadget-knn "$dir/snap.gadget" --mode slice --plane 0,0,0,0,0,1
prun 4 gadget-m4 "$dir/snap.gadget" --kernel m4
prun 2 rbf-dvr "$dir/terms.rbf"
prun 4 rbf-octree "$dir/terms.rbf" --mode iso --iso 0.3 --rbf-accel octree
# three atoms over four ranks: a rank without particles
python3 -c "open('$dir/three.xyz', 'w').write('C 0 0 0\nO 1.2 0 0\nC 0 1.3 0.4\n')"
prun 4 more-ranks-than-particles "$dir/three.xyz" --mode mip
if /usr/bin/python3 -c "import h5py, numpy" 2>/dev/null && "$exe" formats 2>/dev/null | grep -q "^ *hdf5  *yes"; then
    /usr/bin/python3 - "$dir" <<'PY'
import sys, h5py, numpy as np
rng = np.random.default_rng(3)
with h5py.File(sys.argv[1] + "/snap.hdf5", "w") as f:
    h = f.create_group("Header")
    h.attrs["NumPart_ThisFile"] = np.array([500, 0, 0, 0, 0, 0], dtype=np.int32)
    h.attrs["NumPart_Total"] = np.array([500, 0, 0, 0, 0, 0], dtype=np.uint32)
    h.attrs["MassTable"] = np.zeros(6)
    h.attrs["NumFilesPerSnapshot"] = 1
    g = f.create_group("PartType0")
    g["Coordinates"] = (rng.random((500, 3)) * rng.random((500, 3))).astype(np.float32)
    g["SmoothingLength"] = (0.05 + 0.1 * rng.random(500)).astype(np.float32)
    g["Masses"] = np.ones(500, dtype=np.float32)
# a second file: gas with Density and InternalEnergy (the normalised interpolant's m / rho)
with h5py.File(sys.argv[1] + "/gas.hdf5", "w") as f:
    h = f.create_group("Header")
    h.attrs["NumPart_ThisFile"] = np.array([700, 0, 0, 0, 0, 0], dtype=np.int32)
    h.attrs["NumPart_Total"] = np.array([700, 0, 0, 0, 0, 0], dtype=np.uint32)
    h.attrs["MassTable"] = np.zeros(6)
    h.attrs["NumFilesPerSnapshot"] = 1
    g = f.create_group("PartType0")
    g["Coordinates"] = (rng.random((700, 3)) * rng.random((700, 3))).astype(np.float32)
    g["SmoothingLength"] = (0.08 + 0.12 * rng.random(700)).astype(np.float32)
    g["Masses"] = (0.5 + rng.random(700)).astype(np.float32)
    g["Density"] = (0.2 + 2.0 * rng.random(700)).astype(np.float32)
    g["InternalEnergy"] = (1.0 + 3.0 * rng.random(700)).astype(np.float32)
PY
    prun 3 hdf5-scattered "$dir/snap.hdf5"
    # --normalise under mpirun: the norm weights m / rho go with each particle to the
    # ranks it reaches; the float image of K = 1..3 ranks is the one process's
    # (--canonical-order 1) exactly: the direct method's gathers sum in one order
    bits norm-m4-slice "1 2 3" "$dir/gas.hdf5" --kernel m4 --value InternalEnergy --normalise --mode slice \
        --plane 0.3,0.3,0.3,0.2,0.3,1 --size 48x40
    # an SPH snapshot with varying smoothing lengths
    bits hdf5-m4-iso "2 4" "$dir/snap.hdf5" --kernel m4 --mode iso --iso 0.3 $inside
else
    echo "skip hdf5 snapshot (needs python3-h5py and a build with HDF5)"
fi

# --stats: a row per rank; the region weights sum to the 3000 particles
if timeout 60 "$mpiexec" --oversubscribe -np 3 "$exe" render $raw --size 40x30 --threads 1 --stats \
    -o "$dir/stats.png" > "$dir/out" 2> "$dir/err" &&
    grep -q "peak_MB" "$dir/out" &&
    [ "$(awk '$1 ~ /^[0-2]$/ && NF >= 10 { s += $3 } END { print s }' "$dir/out")" = 3000 ] &&
    [ "$(sed -n 's/^ *[0-2] .* its share of the file, \([0-9]*\) particles; keeps [0-9]*$/\1/p' "$dir/out" |
        awk '{ s += $1; n++ } END { print n, s }')" = "3 3000" ]; then
    echo "ok   --stats: region weights sum to 3000, the ranks' shares of the file too"
else
    echo "FAIL --stats: $(cat "$dir/out" "$dir/err")"
    fail=1
fi
# --stats of a PDB (read by rank 0): every row says so
if timeout 60 "$mpiexec" --oversubscribe -np 2 "$exe" render "$dir/mol.pdb" --size 40x30 --threads 1 --stats \
    -o "$dir/statsp.png" > "$dir/out" 2> "$dir/err" &&
    [ "$(grep -c "^ *[01] .* keeps [0-9]* of rank 0's whole read (the format is read by one rank)$" "$dir/out")" = 2 ]; then
    echo "ok   --stats of a PDB: both ranks' particles from rank 0's read"
else
    echo "FAIL --stats of a PDB: $(cat "$dir/out" "$dir/err")"
    fail=1
fi

# a file 20 bytes short: only the last rank reads its end; all exit non-zero with its message
set +e
timeout 60 "$mpiexec" --oversubscribe -np 3 "$exe" render "$dir/short.f32" --raw-particles 3000 --radius 0.05 \
    --size 40x30 --threads 1 -o "$dir/bad.png" > "$dir/out" 2> "$dir/err"
rc=$?
set -e
if [ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q "rank 2: .*short.f32.*truncated" "$dir/err" && [ ! -e "$dir/bad.png" ]; then
    echo "ok   a truncated file: exit $rc: $(grep -m1 'rank 2' "$dir/err")"
else
    echo "FAIL a truncated file: exit $rc (124: timed out): $(cat "$dir/err")"
    fail=1
fi
exit $fail
