#!/bin/sh
# Kernel objects export only target-suffixed symbols (STYLE.md "Names": one
# source compiled per target must not collide), and the shared library
# exports only the public lc_ API. usage: test_symbols.sh BUILD_DIR
set -eu
build=$1
fail=0 nlibs=0
# Target names of the kernel libraries, longest first: a symbol belongs to the
# longest target name it ends with, so "lc_ktable_avx512_8" counts as avx512_8
# (not as some avx512 symbol) and vice versa; each library must hold only its
# own target's symbols.
targets=$(for lib in "$build"/liblc_kernels_*.a; do
    [ -e "$lib" ] || continue
    t=$(basename "$lib" .a); echo "${t#liblc_kernels_}"
done | awk '{print length($0), $0}' | sort -rn | cut -d' ' -f2)
owner() { # owner SYMBOL: the longest target name SYMBOL ends with as _<t>, or nothing
    for o in $targets; do
        case "$1" in *_"$o") echo "$o"; return;; esac
    done
}
ref_bases="" ref_t=""
for lib in "$build"/liblc_kernels_*.a; do
    [ -e "$lib" ] || continue
    nlibs=$((nlibs + 1))
    t=$(basename "$lib" .a); t=${t#liblc_kernels_}
    # meson's static libraries are thin archives: nm must run in place
    syms=$(nm -g --defined-only "$lib") || { echo "FAIL nm $lib"; exit 1; }
    defined=$(echo "$syms" | awk 'NF == 3 && $2 ~ /^[TDRB]$/ {print $3}')
    bad=$(for s in $defined; do [ "$(owner "$s")" = "$t" ] || echo "$s"; done)
    n=$(echo "$defined" | grep -c . || true)
    # the same entry points in every library, only the suffix differs
    bases=$(for s in $defined; do echo "${s%_"$t"}"; done | sort)
    if ! echo "$defined" | grep -qx "lc_ktable_$t"; then
        echo "FAIL $(basename "$lib"): no lc_ktable_$t (is nm reading the right objects?)"
        fail=1
    elif [ -n "$bad" ]; then
        echo "FAIL $(basename "$lib"): globals that do not end in exactly _$t:"; echo "$bad" | sed 's/^/       /'
        fail=1
    elif [ -n "$ref_t" ] && [ "$bases" != "$ref_bases" ]; then
        echo "FAIL $(basename "$lib"): entry points differ from liblc_kernels_$ref_t.a:"
        printf '%s\n' "$ref_bases" >"${TMPDIR:-/tmp}/lc_sym_ref.$$"
        printf '%s\n' "$bases" | diff "${TMPDIR:-/tmp}/lc_sym_ref.$$" - | sed 's/^/       /'
        rm -f "${TMPDIR:-/tmp}/lc_sym_ref.$$"
        fail=1
    else
        echo "ok   $(basename "$lib"): $n defined globals, all end in exactly _$t"
    fi
    [ -n "$ref_t" ] || { ref_t=$t; ref_bases=$bases; }
done
[ "$nlibs" -gt 0 ] || { echo "FAIL no kernel libraries under $build"; exit 1; }
so=$(find "$build" -maxdepth 1 -type f -name "liblanecast.so.*" | head -n 1)
dyn=$(nm -D --defined-only "$so") || { echo "FAIL nm -D $so"; exit 1; }
bad=$(echo "$dyn" | awk '{print $NF}' | grep -v '^lc_' || true)
n=$(echo "$dyn" | grep -c ' lc_' || true)
if [ -n "$bad" ]; then
    echo "FAIL $(basename "$so") exports symbols outside lc_:"; echo "$bad" | sed 's/^/       /'
    fail=1
else
    echo "ok   $(basename "$so"): $n exported symbols, all lc_*"
fi
[ "$fail" -eq 0 ] && echo "PASS test_symbols"
exit $fail
