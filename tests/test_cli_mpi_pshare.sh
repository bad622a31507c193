#!/bin/sh
# mpiexec -np K lanecast render of HDF5 and GADGET snapshots read by shares
# (host/mpi/mpi_pload.c, lci_share): when every quantity is per particle
# (SmoothingLength / HSML radii, the value, masses and densities) each rank
# reads rows [a, b) of the whole read's order itself.
# - Float images (EXR, view_imgcmp exact) of K = 1..4 equal one process's
#   (its defaults: the canonical BVH): an HDF5 snapshot of two PartTypes (a share
#   spans both groups) and GADGET format 1 and 2 gas, varying smoothing
#   lengths, SPH interpolation (k = m / rho * u) and --normalise.
# - No rank reads the whole file: with LANECAST_TEST_FAULT=whole (rank 0's
#   whole read fails) the shared loads still render; the control, a file
#   without smoothing lengths (k-nearest radii need the whole set), fails
#   with the fault's message, so the hook fires on the whole path.
# - Lying counts (NumPart_ThisFile against Coordinates, SmoothingLength
#   shorter than Coordinates, a GADGET header counting more gas than its
#   HSML block holds): every rank exits non-zero with the message within
#   the timeout, no image.
# usage: test_cli_mpi_pshare.sh LANECAST MPIEXEC VIEW_IMGCMP
set -eu
exe=$1
mpiexec=$2
imgcmp=$3
. "$(dirname "$0")/cli_mpi_run.sh" # $dir, run, bits
if ! /usr/bin/python3 -c "import h5py, numpy" 2>/dev/null || ! "$exe" formats 2>/dev/null | grep -q "^ *hdf5  *yes"; then
    echo "skip: needs python3-h5py and a build with HDF5"
    exit 77
fi
/usr/bin/python3 - "$dir" <<'PY'
import struct, sys, h5py, numpy as np
d = sys.argv[1]
rng = np.random.default_rng(11)
def clumpy(n):  # clustered towards a corner: kd splits are not the box's halves
    return (rng.random((n, 3)) * rng.random((n, 3))).astype(np.float32)
def header(f, counts):
    h = f.create_group("Header")
    h.attrs["NumPart_ThisFile"] = np.array(counts, dtype=np.int32)
    h.attrs["NumPart_Total"] = np.array(counts, dtype=np.uint32)
    h.attrs["MassTable"] = np.zeros(6)
    h.attrs["NumFilesPerSnapshot"] = 1
def group(f, t, n, hsml=True):
    g = f.create_group("PartType%d" % t)
    g["Coordinates"] = clumpy(n)
    if hsml:
        g["SmoothingLength"] = (0.05 + 0.12 * rng.random(n)).astype(np.float32)
    g["Masses"] = (0.5 + rng.random(n)).astype(np.float32)
    g["Density"] = (0.2 + 2.0 * rng.random(n)).astype(np.float32)
    g["InternalEnergy"] = (1.0 + 3.0 * rng.random(n)).astype(np.float32)
    return g
with h5py.File(d + "/two.hdf5", "w") as f:  # gas and a second type with smoothing lengths
    header(f, [600, 0, 0, 0, 301, 0])
    group(f, 0, 600), group(f, 4, 301)
with h5py.File(d + "/knn.hdf5", "w") as f:  # no smoothing lengths: k-nearest radii
    header(f, [0, 500, 0, 0, 0, 0])
    group(f, 1, 500, hsml=False)
with h5py.File(d + "/numpart.hdf5", "w") as f:  # the header counts more than Coordinates holds
    header(f, [700, 0, 0, 0, 0, 0])
    group(f, 0, 600)
with h5py.File(d + "/short-hsml.hdf5", "w") as f:  # SmoothingLength one row short
    header(f, [600, 0, 0, 0, 0, 0])
    g = group(f, 0, 600, hsml=False)
    g["SmoothingLength"] = (0.05 + 0.12 * rng.random(599)).astype(np.float32)
# GADGET gas (type 0): POS VEL ID MASS U RHO HSML, the mass table 0
n = 700
pos, u = clumpy(n), (1.0 + 3.0 * rng.random(n)).astype(np.float32)
mass, rho = (0.5 + rng.random(n)).astype(np.float32), (0.2 + 2.0 * rng.random(n)).astype(np.float32)
hsml = (0.06 + 0.12 * rng.random(n)).astype(np.float32)
def head(npart):
    b = struct.pack("<6i", npart, 0, 0, 0, 0, 0) + struct.pack("<6d", 0, 0, 0, 0, 0, 0) + struct.pack("<2d", 1.0, 0.0)
    b += struct.pack("<2i", 0, 0) + struct.pack("<6I", npart, 0, 0, 0, 0, 0) + struct.pack("<2i", 0, 1) + struct.pack("<d", 0.0)
    return b + b"\0" * (256 - len(b))
def rec(b):
    return struct.pack("<i", len(b)) + b + struct.pack("<i", len(b))
blocks = [("POS ", pos.tobytes()), ("VEL ", b"\0" * (12 * n)), ("ID  ", np.arange(n, dtype=np.uint32).tobytes()),
          ("MASS", mass.tobytes()), ("U   ", u.tobytes()), ("RHO ", rho.tobytes()), ("HSML", hsml.tobytes())]
def gadget(path, fmt, npart):
    with open(path, "wb") as f:
        for name, data in [("HEAD", head(npart))] + blocks:
            if fmt == 2:
                f.write(rec(name.encode() + struct.pack("<i", len(data) + 8)))
            f.write(rec(data))
gadget(d + "/gas.gadget", 1, n)
gadget(d + "/gas2.gadget", 2, n)
gadget(d + "/lying.gadget", 1, n + 40)  # the header counts 40 gas particles more than the blocks hold
PY

inside="--eye 0.3,0.25,0.2 --at 1,0.8,0.6 --fov 70"
ortho="--eye -3,1.5,2 --at 0.3,0.3,0.3 --ortho 1.5"
plane="--plane 0.3,0.3,0.3,0.2,0.3,1"

# bit for bit: the shares' images are one process's
bits h5-two-m4-iso "1 2 3 4" "$dir/two.hdf5" --kernel m4 --mode iso --iso 0.3 $ortho
bits h5-two-u-slice "1 2 3 4" "$dir/two.hdf5" --kernel m4 --value u --mode slice $plane $ortho
bits h5-two-mip-inside "2 3" "$dir/two.hdf5" --mode mip $inside
bits h5-norm-slice "2 4" "$dir/two.hdf5" --kernel wendland-c2 --value u --normalise --mode slice $plane
bits gadget-m4-iso "1 2 3 4" "$dir/gas.gadget" --kernel m4 --mode iso --iso 0.3 $ortho
bits gadget-u-slice "1 2 3 4" "$dir/gas.gadget" --kernel m4 --value u --mode slice $plane $ortho
bits gadget2-norm-slice "2 3" "$dir/gas2.gadget" --kernel m4 --value u --normalise --mode slice $plane

# no rank reads the whole file: rank 0's whole read fails under the fault, the shares do not
whole() { # NAME EXPECT(ok|fault) FILE ARGS...
    name=$1 want=$2 file=$3
    shift 3
    set +e
    timeout 60 "$mpiexec" --oversubscribe -np 3 -x LANECAST_TEST_FAULT=whole "$exe" render "$file" "$@" \
        --size 40x30 --threads 1 --quiet -o "$dir/whole-$name.png" > "$dir/out" 2> "$dir/err"
    rc=$?
    set -e
    if [ "$want" = ok ] && [ $rc -eq 0 ] && [ -s "$dir/whole-$name.png" ]; then
        echo "ok   $name: read by shares (rank 0's whole read under the fault 'whole' not taken)"
    elif [ "$want" = fault ] && [ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q "test fault 'whole'" "$dir/err" &&
        [ ! -e "$dir/whole-$name.png" ]; then
        echo "ok   $name: read whole by rank 0 (the control: the fault fires): exit $rc"
    else
        echo "FAIL $name: want $want, exit $rc (124: timed out): $(cat "$dir/err")"
        fail=1
    fi
}
whole h5-shares ok "$dir/two.hdf5" --kernel m4 --value u
whole gadget-shares ok "$dir/gas.gadget" --kernel m4
whole gadget2-shares ok "$dir/gas2.gadget" --mode mip
whole h5-knn fault "$dir/knn.hdf5"
whole gadget-select fault "$dir/gas.gadget" --select "index 0:300"
whole h5-select fault "$dir/two.hdf5" --select "type 4"

# lying counts: every rank exits non-zero with the message, promptly, no image
bad() { # NAME PATTERN FILE
    set +e
    timeout 60 "$mpiexec" --oversubscribe -np 3 "$exe" render "$3" --kernel m4 --size 40x30 --threads 1 \
        -o "$dir/bad-$1.png" > "$dir/out" 2> "$dir/err"
    rc=$?
    set -e
    if [ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q "$2" "$dir/err" && [ ! -e "$dir/bad-$1.png" ]; then
        echo "ok   $1: exit $rc: $(grep -m1 "$2" "$dir/err")"
    else
        echo "FAIL $1: exit $rc (124: timed out): $(cat "$dir/err")"
        fail=1
    fi
}
bad h5-numpart "NumPart_ThisFile\[0\] says 700" "$dir/numpart.hdf5"
bad h5-short-hsml "SmoothingLength.*expected 600 rows" "$dir/short-hsml.hdf5"
bad gadget-lying "block.*HSML\|POS block" "$dir/lying.gadget"
exit $fail
