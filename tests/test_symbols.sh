#!/bin/sh
# Kernel objects export only target-suffixed symbols (STYLE.md "Names": one
# source compiled per target must not collide), and the shared library
# exports only the public lc_ API. usage: test_symbols.sh BUILD_DIR
set -eu
build=$1
fail=0 nlibs=0
for lib in "$build"/liblc_kernels_*.a; do
    [ -e "$lib" ] || continue
    nlibs=$((nlibs + 1))
    t=$(basename "$lib" .a); t=${t#liblc_kernels_}
    # meson's static libraries are thin archives: nm must run in place
    syms=$(nm -g --defined-only "$lib") || { echo "FAIL nm $lib"; exit 1; }
    defined=$(echo "$syms" | awk 'NF == 3 && $2 ~ /^[TDRB]$/ {print $3}')
    bad=$(echo "$defined" | grep -v "_${t}\$" || true)
    n=$(echo "$defined" | grep -c . || true)
    if ! echo "$defined" | grep -qx "lc_ktable_$t"; then
        echo "FAIL $(basename "$lib"): no lc_ktable_$t (is nm reading the right objects?)"
        fail=1
    elif [ -n "$bad" ]; then
        echo "FAIL $(basename "$lib"): globals without the _$t suffix:"; echo "$bad" | sed 's/^/       /'
        fail=1
    else
        echo "ok   $(basename "$lib"): $n defined globals, all end in _$t"
    fi
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
