#!/bin/sh
# mpiexec -np K lanecast render: the PNG rank 0 writes equals the
# one-process PNG byte for byte (mip, iso, slice and, by the chain, dvr with
# alpha_stop 1 are the same floats; EXR and TIFF files carry a time stamp), HDF5 grids read by
# hyperslab per rank included; --stats prints a line per rank, naming the nodes
# each read (a gzip file: its part of rank 0's read, and why); a bad input on some ranks
# (MPMD: other ranks get a missing file) makes every rank exit non-zero
# with that rank's message, within a timeout. usage: test_cli_mpi.sh LANECAST MPIEXEC
set -eu
exe=$1
mpiexec=$2
. "$(dirname "$0")/cli_mpi_run.sh" # $dir, run
python3 "$(dirname "$0")/cli_scenes.py" "$dir" # ball.raw, atoms.xyz, set.rbf
vol="$dir/ball.raw --dims 16,16,16 --type float32"
run 2 grid-dvr png $vol --alpha-stop 1
run 3 grid-iso png $vol --mode iso --iso 0.5 --shade phong --eye 8,8,8 --at 20,9,3
run 2 atoms-mip png "$dir/atoms.xyz" --mode mip --ortho 12
run 3 rbf-slice png "$dir/set.rbf" --mode slice --plane 0,0,0,0,0,1
run 4 grid-1x1 png $vol --mode mip --size 1x1
# each rank reads its part (NRRD, MetaImage, NIfTI) or gets it from rank 0 (gzip);
# the default TF comes from the histogram summed over ranks
run 3 nrrd-part png "$dir/ball.nhdr" --alpha-stop 1 --shade phong
run 2 mhd-part png "$dir/ball.mhd" --mode iso --iso 0.4 --shade phong
if "$exe" formats 2>/dev/null | grep -q "^ *nifti  *yes"; then run 4 nifti-part png "$dir/ball.nii" --mode mip; fi
if "$exe" formats 2>/dev/null | grep -q "^ *zlib  *yes"; then run 3 gzip-scattered png "$dir/ballz.nhdr" --alpha-stop 1; fi
run 2 histogram-summed png "$dir/half.raw" --dims 16,16,16 --type float32 --alpha-stop 1 --view 30,20
# HDF5 grid datasets read by hyperslab per rank (contiguous uint8, chunked and gzip float32,
# int16 with a non-cubic shape); a dataset that is not 3-D fails on every rank
if /usr/bin/python3 -c "import h5py, numpy" 2>/dev/null && "$exe" formats 2>/dev/null | grep -q "^ *hdf5  *yes"; then
    /usr/bin/python3 - "$dir" <<'PY'
import sys, h5py, numpy as np
z, y, x = np.mgrid[0:18, 0:20, 0:23].astype(np.float32)
ball = np.exp(-((x - 11) ** 2 + (y - 9) ** 2 + (z - 8) ** 2) / 40.0) + 0.1 * np.sin(x / 3.0)
with h5py.File(sys.argv[1] + "/grid.h5", "w") as f:
    f["u8"] = np.clip(ball * 255, 0, 255).astype(np.uint8)
    f.create_dataset("f32", data=ball.astype(np.float32), chunks=(5, 7, 6), compression="gzip")
    f["i16"] = (ball * 3000 - 200).astype(np.int16)
    f["flat"] = np.zeros((4, 5), dtype=np.float32)
PY
    run 2 hdf5-u8 png "$dir/grid.h5" --dataset /u8 --alpha-stop 1
    run 3 hdf5-f32-chunked png "$dir/grid.h5" --dataset /f32 --mode iso --iso 0.5 --shade phong
    run 4 hdf5-i16 png "$dir/grid.h5" --dataset /i16 --mode mip --eye 30,30,30 --at 11,9,8
    set +e
    timeout 60 "$mpiexec" --oversubscribe -np 2 "$exe" render "$dir/grid.h5" --dataset /flat --size 40x30 \
        --threads 1 -o "$dir/flat.png" > "$dir/out" 2> "$dir/err"
    rc=$?
    set -e
    if [ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q "flat" "$dir/err" && [ ! -e "$dir/flat.png" ]; then
        echo "ok   hdf5 2-D dataset: exit $rc: $(head -1 "$dir/err")"
    else
        echo "FAIL hdf5 2-D dataset: exit $rc (124: timed out): $(cat "$dir/err")"
        fail=1
    fi
else
    echo "skip hdf5 grids (needs python3-h5py and a build with HDF5)"
fi

# --stats: rank 0 prints one row per rank and the imbalance
if timeout 60 "$mpiexec" --oversubscribe -np 3 "$exe" render $vol --size 40x30 --threads 1 --stats \
    -o "$dir/stats.png" > "$dir/out" 2> "$dir/err" &&
    grep -q "^mpi .*3 ranks, the chain .*render imbalance" "$dir/out" && grep -q "peak_MB" "$dir/out" &&
    [ "$(grep -c '^ *[0-2] ' "$dir/out")" -ge 3 ] &&
    [ "$(grep -c '^ *[0-2] .* nodes [0-9]*\.\.[0-9]* x [0-9]*\.\.[0-9]* x [0-9]*\.\.[0-9]* of the file$' "$dir/out")" = 3 ]; then
    echo "ok   --stats per rank (each read its nodes of the file)"
else
    echo "FAIL --stats per rank: $(cat "$dir/out" "$dir/err")"
    fail=1
fi
# --stats of a gzip grid: every rank's row says it got its part of rank 0's read, and why
if "$exe" formats 2>/dev/null | grep -q "^ *zlib  *yes"; then
    if timeout 60 "$mpiexec" --oversubscribe -np 2 "$exe" render "$dir/ballz.nhdr" --size 40x30 --threads 1 --stats \
        -o "$dir/statsz.png" > "$dir/out" 2> "$dir/err" &&
        [ "$(grep -c "^ *[01] .* its part of rank 0's whole read (compressed voxels are read whole)$" "$dir/out")" = 2 ]; then
        echo "ok   --stats of a gzip grid: the parts came from rank 0, the reason named"
    else
        echo "FAIL --stats of a gzip grid: $(cat "$dir/out" "$dir/err")"
        fail=1
    fi
fi

# a bad input on ranks 1 and 2 (a missing file): all three exit non-zero, naming rank 1's file
set +e
timeout 60 "$mpiexec" --oversubscribe -np 1 "$exe" render $vol --size 40x30 --threads 1 -o "$dir/bad.png" : \
    -np 2 "$exe" render "$dir/missing.raw" --dims 16,16,16 --type float32 --size 40x30 --threads 1 -o "$dir/bad.png" \
    > "$dir/out" 2> "$dir/err"
rc=$?
set -e
if [ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q "rank 1: .*missing.raw" "$dir/err" && [ ! -e "$dir/bad.png" ]; then
    echo "ok   a missing file on ranks 1-2: exit $rc, rank 0 says: $(grep 'rank 1' "$dir/err" | head -1)"
else
    echo "FAIL a missing file on ranks 1-2: exit $rc (124: timed out): $(cat "$dir/err")"
    fail=1
fi
exit $fail
