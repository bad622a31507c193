#!/bin/sh
# RBF encoder benchmark (docs/bench/rbf.md): encode time against volume
# size (embryo resampled to 64^3, 128^3 and 256^3, a fixed 256 RBFs), RMS
# error against RBF count for hydrogen, neghip and headsq (the encoder's
# per-iteration report), the RBFs and time to the default 2 % target, and the rendered RBF set against the rendered grid
# (same camera, TF, step and range): PSNR.
# Usage: bench/encode_bench.sh BUILD_DIR DATA_DIR OUT_DIR
set -eu
build=$1 data=$2 out=$3
exe=$build/tools/lanecast
py=/usr/bin/python3   # Debian's, with python3-numpy and python3-matplotlib
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "# machine: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2), load $(cut -d' ' -f1-3 /proc/loadavg)" > "$out/encode_scaling.txt"
$py - "$data/volumes/embryo.raw.gz" "$tmp" <<'PY'
import gzip, sys, numpy as np
a = np.frombuffer(gzip.open(sys.argv[1]).read(), dtype=np.uint8).reshape(256, 256, 256).astype(np.float32)
for n in (64, 128, 256):
    f = 256 // n
    b = a.reshape(n, f, n, f, n, f).mean(axis=(1, 3, 5)).astype(np.uint8)
    hdr = b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\nspacings: %d %d %d\nencoding: raw\n\n" % (n, n, n, f, f, f)
    open("%s/embryo%d.nrrd" % (sys.argv[2], n), "wb").write(hdr + b.tobytes())
PY
for n in 64 128 256; do
    /usr/bin/time -f "cpu %U s user" "$exe" encode "$tmp/embryo$n.nrrd" -o "$tmp/e$n.rbf" --max-rbfs 256 --max-error 0.001 \
        --centre maxerr > "$tmp/e$n.txt" 2> "$tmp/e$n.cpu"
    printf "size %d samples %d %s %s\n" $n $((n * n * n)) "$(grep -E '^(error|time)' "$tmp/e$n.txt" | tr -s ' ' | tr '\n' ' ')" \
        "$(tail -1 "$tmp/e$n.cpu")" >> "$out/encode_scaling.txt"
done
: > "$out/encode_rms.txt"
for v in hydrogen neghip headsq; do
    "$exe" encode "$data/volumes/$v.nhdr" -o "$tmp/$v.rbf" --max-rbfs 2048 --max-error 0.005 --centre maxerr --progress \
        2> "$tmp/$v.progress" > "$tmp/$v.txt"
    sed -n "s/^encode: \([0-9]*\) RBFs.*RMS \([0-9.]*\)% .*, \([0-9.]*\) s$/$v \1 \2 \3/p" "$tmp/$v.progress" >> "$out/encode_rms.txt"
    printf "%s final %s\n" $v "$(grep -E '^(rbfs|error|time)' "$tmp/$v.txt" | tr -s ' ' | tr '\n' ' ')" >> "$out/encode_rms.txt"
done
# RBFs to the default 2 % target (the count, the time), --centre maxerr
: > "$out/encode_target.txt"
for v in hydrogen neghip headsq; do
    /usr/bin/time -f "cpu %U s user" "$exe" encode "$data/volumes/$v.nhdr" -o "$tmp/$v-2.rbf" --max-rbfs 8000 --centre maxerr \
        > "$tmp/$v-2.txt" 2> "$tmp/$v-2.cpu"
    printf "%s 2%% %s %s\n" $v "$(grep -E '^(rbfs|error|time)' "$tmp/$v-2.txt" | tr -s ' ' | tr '\n' ' ')" \
        "$(tail -1 "$tmp/$v-2.cpu")" >> "$out/encode_target.txt"
done
# PSNR: grid against its encoding at 2% RMS (hydrogen, neghip)
: > "$out/encode_psnr.txt"
for spec in "hydrogen 0 1 --max-error 0.02" "neghip 0 255 --max-error 0.02"; do
    set -- $spec
    v=$1 lo=$2 hi=$3
    shift 3
    "$exe" encode "$data/volumes/$v.nhdr" -o "$tmp/$v-p.rbf" --centre maxerr --quiet "$@"
    view="--size 256x256 --eye 31.5,31.5,200 --at 31.5,31.5,31.5 --range $lo,$hi --tf heat --tau 0.3 --dt 0.25 --alpha-stop 1"
    "$exe" render "$data/volumes/$v.nhdr" -o "$out/encode_${v}_grid.png" $view --quiet
    "$exe" render "$tmp/$v-p.rbf" -o "$out/encode_${v}_rbf.png" $view --domain 0,0,0,63,63,63 --quiet
    printf "%s %s %s\n" $v "$*" "$($py -c "
import matplotlib.image as m, numpy as np, sys
a = m.imread('$out/encode_${v}_grid.png')[..., :3].astype(float); b = m.imread('$out/encode_${v}_rbf.png')[..., :3].astype(float)
mse = ((a - b) ** 2).mean(); print('PSNR %.2f dB, max diff %.3f' % (10 * np.log10(1 / mse), abs(a - b).max()))")" >> "$out/encode_psnr.txt"
done
cat "$out/encode_scaling.txt" "$out/encode_rms.txt" "$out/encode_target.txt" "$out/encode_psnr.txt"
