#!/bin/sh
# lanecast render's per-atom flags on files this script writes: --value and
# --field-by column NAME on a PDB (the fields --stats reports), --select on
# CSV and mmCIF, and the failures (one line naming the file and the column
# or keyword, exit status 1, no image); --help names the flags per format.
# usage: test_cli_formats_opts.sh LANECAST_EXE
set -u
exe=$1
fail=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ok() { echo "ok   $*"; }
no() { echo "FAIL $*"; fail=1; }

# 4 atoms, chains A A B C, b-factors 10 20 30 40
for i in 1 2 3 4; do
    chain=$(echo "A A B C" | cut -d' ' -f$i)
    printf 'ATOM  %5d  CA  ALA %s%4d    %8.3f%8.3f%8.3f%6.2f%6.2f           C\n' $i "$chain" $i $((i * 2)) 0 0 1 $((i * 10))
done >"$tmp/x.pdb"
printf 'x,y,z,type,resname\n0,0,0,1,ALA\n2,0,0,2,HOH\n4,0,0,1,HOH\n' >"$tmp/x.csv"
printf 'data_x\nloop_\n_atom_site.type_symbol\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n_atom_site.label_comp_id\nC 0 0 0 ALA\nO 2 0 0 HOH\n' >"$tmp/x.cif"

"$exe" render "$tmp/x.pdb" --value bfactor --field-by column chain --size 32x32 --stats -o "$tmp/b.png" >"$tmp/out" 2>&1
[ $? -eq 0 ] && [ -s "$tmp/b.png" ] && grep -q '^particles     4 (0 dropped), 3 fields' "$tmp/out" &&
    ok "render x.pdb --value bfactor --field-by column chain: 3 fields" || { no "--field-by column chain:"; cat "$tmp/out"; }
"$exe" render "$tmp/x.pdb" --value colour --size 32x32 -o "$tmp/c.png" 2>"$tmp/err"
[ $? -eq 1 ] && [ ! -e "$tmp/c.png" ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] &&
    grep -q "x.pdb: value = 'colour': PDB records have no such column" "$tmp/err" &&
    ok "--value colour fails: $(cat "$tmp/err")" || { no "--value colour:"; cat "$tmp/err"; }
"$exe" render "$tmp/x.csv" --select 'resname HOH and type 1' --radius 1 --size 32x32 --stats -o "$tmp/s.png" >"$tmp/out" 2>&1
[ $? -eq 0 ] && grep -q '^particles     1 ' "$tmp/out" &&
    ok "render x.csv --select 'resname HOH and type 1': 1 particle" || { no "csv --select:"; cat "$tmp/out"; }
"$exe" render "$tmp/x.csv" --select 'chain A' --radius 1 --size 32x32 -o "$tmp/s2.png" 2>"$tmp/err"
[ $? -eq 1 ] && [ ! -e "$tmp/s2.png" ] && grep -q "keyword 'chain' does not apply to csv files" "$tmp/err" &&
    ok "csv --select 'chain A' fails: $(cat "$tmp/err")" || { no "csv chain:"; cat "$tmp/err"; }
"$exe" render "$tmp/x.cif" --select 'segid A' --size 32x32 -o "$tmp/m.png" 2>"$tmp/err"
[ $? -eq 1 ] && [ ! -e "$tmp/m.png" ] && grep -q "keyword 'segid' .*mmcif file" "$tmp/err" &&
    ok "mmcif --select 'segid A' fails: $(cat "$tmp/err")" || { no "mmcif segid:"; cat "$tmp/err"; }
"$exe" render --help >"$tmp/help" 2>&1
grep -q -- '--value COLUMN' "$tmp/help" && grep -q 'occupancy, bfactor' "$tmp/help" && grep -q 'column NAME' "$tmp/help" &&
    grep -q 'mmCIF any _atom_site item' "$tmp/help" &&
    ok "render --help describes --value and --field-by column per format" || no "render --help"
exit $fail
