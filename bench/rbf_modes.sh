#!/bin/sh
# Frame rate of an encoded RBF set (coherent, BVH gather and octree) against
# its original grid, for every render mode, at 1024^2 (docs/bench/rbf.md).
# The same camera, transfer function, value range and step for all four;
# the RBF set renders inside the grid's box (--domain), so both sample the
# same lattice. Each case: one warm-up, then REPEATS frames; the median of
# the render times `--stats` prints. Rounds interleave the three so load
# drift on a shared machine falls on all alike. METHODS picks RBF methods
# (default "coherent bvh octree"; a method left out prints "-").
# Usage: bench/rbf_modes.sh BUILD_DIR DATA_DIR OUT_FILE [REPEATS]
set -eu
build=$1 data=$2 out=$3 reps=${4:-5}
exe=$build/tools/lanecast
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
size=${SIZE:-1024x1024}

# volume, encoder flags, box max, iso value, range (the data's units)
cases=${CASES:-"hydrogen|--max-error 0.02|63|0.3|0,1
neghip|--max-error 0.02|65|120|0,255"}

median() { sort -g | awk '{a[NR] = $1} END {if (NR) print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

render_time() { # prints the render seconds of one frame
    "$exe" render "$@" --size "$size" --stats --quiet -o "$tmp/img.exr" 2>&1 | awk '/^render /{print $2}'
}

{
echo "# machine: $(nproc) CPUs,$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2); commit $(git -C "$(dirname "$0")" rev-parse --short HEAD)"
echo "# $size, default target and threads, median of $reps frames after a warm-up; seconds per frame"
echo "volume rbfs mode grid_s rbf_coherent_s rbf_bvh_s rbf_octree_s grid_fps coherent_fps bvh_fps octree_fps"
echo "$cases" | while IFS='|' read -r vol enc hi iso range; do
    src="$data/volumes/$vol.nhdr"
    # shellcheck disable=SC2086
    "$exe" encode "$src" -o "$tmp/$vol.rbf" $enc > "$tmp/$vol.enc" 2>/dev/null
    n=$(awk '/^rbfs/{print $2 + 0}' "$tmp/$vol.enc")
    c=$(awk -v h="$hi" 'BEGIN{print h / 2}')
    common="--eye $c,$c,$(awk -v h="$hi" 'BEGIN{print h * 2.6}') --at $c,$c,$c --tf heat --tau 0.3 --range $range --dt 0.5 --alpha-stop 1"
    for mode in ${MODES:-dvr mip iso slice}; do
        case $mode in
        iso) mflags="--mode iso --iso $iso --shade phong" ;;
        slice) mflags="--mode slice --plane $c,$c,$c,0,0,1 --plane $c,$c,$c,1,0,0" ;;
        *) mflags="--mode $mode" ;;
        esac
        for r in $(seq 0 "$reps"); do
            # shellcheck disable=SC2086
            g=$(render_time "$src" $common $mflags)
            line="$g"
            for me in coherent bvh octree; do
                case " ${METHODS:-coherent bvh octree} " in
                *" $me "*) ;;
                *) line="$line -"; continue ;;
                esac
                case $me in
                octree) how="--rbf-accel octree" ;;
                *) how="--method $me" ;;
                esac
                # shellcheck disable=SC2086
                line="$line $(render_time "$tmp/$vol.rbf" --domain 0,0,0,$hi,$hi,$hi $how $common $mflags)"
            done
            [ "$r" -gt 0 ] && echo "$line" >> "$tmp/$vol.$mode"
        done
        col() { cut -d' ' -f"$1" "$tmp/$vol.$mode" | grep -v -- - | median; }
        gs=$(col 1) cs=$(col 2) bs=$(col 3) os=$(col 4)
        awk -v v="$vol" -v n="$n" -v m="$mode" -v g="$gs" -v c="$cs" -v b="$bs" -v o="$os" '
            function s(x) { return x == "" ? "-" : sprintf("%.4f", x) }
            function f(x) { return x == "" ? "-" : sprintf("%.2f", 1 / x) }
            BEGIN{printf "%s %s %s %s %s %s %s %s %s %s %s\n", v, n, m, s(g), s(c), s(b), s(o), f(g), f(c), f(b), f(o)}'
    done
done
} > "$out"
cat "$out"
