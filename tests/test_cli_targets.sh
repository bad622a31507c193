#!/bin/sh
# The lanecast command line: version, help, targets, LANECAST_TARGET, exit codes.
# usage: test_cli_targets.sh LANECAST_EXE
set -u
exe=$1
fail=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
check() { # check DESCRIPTION COMMAND...: prints ok/FAIL
    desc=$1; shift
    if "$@"; then echo "ok   $desc"; else echo "FAIL $desc"; fail=1; fi
}
run() { # run ENV_TARGET ARGS...: stdout, stderr and status into $tmp
    t=$1; shift
    if [ -n "$t" ]; then LANECAST_TARGET=$t "$exe" "$@" >"$tmp/out" 2>"$tmp/err"
    else env -u LANECAST_TARGET "$exe" "$@" >"$tmp/out" 2>"$tmp/err"; fi
    echo $? >"$tmp/rc"
}
rc() { [ "$(cat "$tmp/rc")" -eq "$1" ]; }

run "" --version
check "--version exits 0 and prints 'lanecast <x.y.z>'" sh -c "[ $(cat "$tmp/rc") -eq 0 ] && grep -Eq '^lanecast [0-9]+\.[0-9]+\.[0-9]+$' '$tmp/out'"
run "" --help
check "--help exits 0 and mentions targets" sh -c "[ $(cat "$tmp/rc") -eq 0 ] && grep -q targets '$tmp/out' && grep -q LANECAST_TARGET '$tmp/out'"
run "" targets
for t in scalar sse4 avx2 avx512 avx512_8; do
    check "targets lists $t" sh -c "[ $(cat "$tmp/rc") -eq 0 ] && grep -Eq '^$t +' '$tmp/out'"
done
check "targets marks exactly one active (auto)" sh -c "[ \$(grep -c '\\* (auto)' '$tmp/out') -eq 1 ]"
check "targets: avx512_8 has 8 lanes, avx512 16" sh -c "grep -Eq '^avx512_8 +8 ' '$tmp/out' && grep -Eq '^avx512 +16 ' '$tmp/out'"
if grep -Eq '^avx512 +16 +yes +yes' "$tmp/out"; then
    check "auto picks avx512 (16 lanes), not avx512_8" sh -c "grep -Eq '^avx512 .*\\* \\(auto\\)' '$tmp/out'"
fi
if grep -Eq '^avx512_8 +8 +yes +yes' "$tmp/out"; then
    run avx512_8 targets
    check "LANECAST_TARGET=avx512_8 targets marks avx512_8 active" sh -c "[ $(cat "$tmp/rc") -eq 0 ] && grep -Eq '^avx512_8 .*\\* \\(forced' '$tmp/out' && [ \$(grep -c '\\*' '$tmp/out') -eq 1 ]"
fi
run sse4 targets
check "LANECAST_TARGET=sse4 targets marks sse4 active" sh -c "rc=$(cat "$tmp/rc"); [ \$rc -eq 0 ] && grep -Eq '^sse4 .*\\* \\(forced' '$tmp/out' && [ \$(grep -c '\\*' '$tmp/out') -eq 1 ]"
run bogus targets
code=$(cat "$tmp/rc")
check "LANECAST_TARGET=bogus exits 1 (got $code)" rc 1
check "... with one line on stderr naming 'bogus'" sh -c "[ \$(wc -l <'$tmp/err') -eq 1 ] && grep -q bogus '$tmp/err'"
sed 's/^/     stderr: /' "$tmp/err"
check "... and nothing on stdout" sh -c "[ ! -s '$tmp/out' ]"
run "" frobnicate
check "unknown command exits 2 (got $(cat "$tmp/rc"))" rc 2
check "... and says so on stderr" grep -q frobnicate "$tmp/err"
run "" targets --bogus-option
check "unknown option of targets exits 2" rc 2
# every subcommand's --help exits 0 and shows an example (issue 11)
for sub in render demo targets formats info encode; do
    run "" $sub --help
    check "$sub --help exits 0 and contains an example" sh -c "[ $(cat "$tmp/rc") -eq 0 ] && grep -qi example '$tmp/out'"
done
run "" --help
check "lanecast --help contains an example" grep -qi example "$tmp/out"
[ $fail -eq 0 ] && echo "PASS test_cli_targets" || echo "FAIL test_cli_targets"
exit $fail
