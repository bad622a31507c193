#!/bin/sh
# lanecast formats: one row per format with its options, the optional
# features with yes/no (and the package when no), --help with an example,
# and a usage error for a stray argument. Arg: the lanecast executable.
set -u
exe=$1
fail=0
check() { if eval "$2"; then echo "ok   $1"; else echo "FAIL $1"; fail=1; fi; }
out=$("$exe" formats) || { echo "FAIL lanecast formats exited $?"; exit 1; }
for f in nrrd metaimage pdb xyz gro raw-particles raw-volume; do
    check "row $f" 'printf "%s\n" "$out" | grep -q "^$f "'
done
check "gro row says particles and .gro" 'printf "%s\n" "$out" | grep -q "^gro  *particles  *\.gro "'
check "option keys listed" 'printf "%s\n" "$out" | grep -q "options: radius radius_scale fields"'
check "features: zlib" 'printf "%s\n" "$out" | grep -Eq "^  zlib +(yes|no) "'
check "features: json" 'printf "%s\n" "$out" | grep -Eq "^  json +(yes|no) "'
if printf "%s\n" "$out" | grep -Eq "^  zlib +no "; then
    check "zlib missing names zlib1g-dev" 'printf "%s\n" "$out" | grep -q "not in this build: install zlib1g-dev"'
fi
if printf "%s\n" "$out" | grep -Eq "^  json +no "; then
    check "json missing names libjson-c-dev" 'printf "%s\n" "$out" | grep -q "not in this build: install libjson-c-dev"'
fi
check "--help has an example" '"$exe" formats --help | grep -q "^  lanecast formats"'
check "listed in lanecast --help" '"$exe" --help | grep -q "^  formats "'
"$exe" formats extra >/dev/null 2>&1
rc=$?
check "stray argument is a usage error (2)" '[ $rc -eq 2 ]'
exit $fail
