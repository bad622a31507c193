#!/bin/sh
# The width study rests on avx512_8 being what its name says: AVX-512
# (EVEX, opmask) instructions on 256-bit vectors and never a zmm register,
# and avx2 never an opmask. usage: test_isa.sh BUILD_DIR
set -eu
build=$1
command -v objdump >/dev/null || { echo "skip: no objdump"; exit 77; }
# AddressSanitizer poisons its shadow memory with 512-bit stores in every
# function it instruments: the property holds for builds without sanitizers.
if grep -q -- "-fsanitize=" "$build/build.ninja" 2>/dev/null; then
    echo "skip: a sanitizer build (ASan writes its shadow with zmm stores); the ISA check runs in plain builds"
    exit 77
fi
fail=0 seen=0
dis() { # dis LIB: disassembly of a (thin) static library; objdump finds the members in place
    objdump -d --no-show-raw-insn "$1"
}
for lib in "$build"/liblc_kernels_avx512_8.a "$build"/liblc_kernels_avx2.a; do
    [ -e "$lib" ] || continue
    seen=$((seen + 1))
    d=$(dis "$lib")
    zmm=$(echo "$d" | grep -c '%zmm' || true)
    kreg=$(echo "$d" | grep -c '{%k[1-7]}' || true)
    case "$lib" in
    *avx512_8*)
        if [ "$zmm" -eq 0 ] && [ "$kreg" -gt 0 ]; then echo "ok   $(basename "$lib"): no zmm, $kreg opmask-predicated instructions"
        else echo "FAIL $(basename "$lib"): $zmm instructions on zmm, $kreg with opmasks (want 0 and > 0)"; fail=1; fi ;;
    *)
        if [ "$zmm" -eq 0 ] && [ "$kreg" -eq 0 ]; then echo "ok   $(basename "$lib"): no zmm, no opmasks"
        else echo "FAIL $(basename "$lib"): $zmm zmm and $kreg opmask instructions in an AVX2 library"; fail=1; fi ;;
    esac
done
[ "$seen" -gt 0 ] || { echo "skip: neither avx2 nor avx512_8 compiled"; exit 77; }
[ "$fail" -eq 0 ] && echo "PASS test_isa"
exit $fail
