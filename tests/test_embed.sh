#!/bin/sh
# Installs lanecast into a temporary destdir, builds examples/embed.c against
# it through pkg-config alone (as an embedding project would) and runs it.
# usage: test_embed.sh BUILD_DIR SOURCE_DIR
set -eu
build=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
meson install -C "$build" --destdir "$tmp/root" --no-rebuild >"$tmp/install.log" 2>&1 || {
    cat "$tmp/install.log"; echo "FAIL meson install"; exit 1; }
pc=$(find "$tmp/root" -name lanecast.pc | head -n 1)
[ -n "$pc" ] || { echo "FAIL no lanecast.pc installed"; exit 1; }
echo "ok   installed; pkg-config file $pc"
export PKG_CONFIG_PATH="$(dirname "$pc")"
# Not --define-prefix: it guesses the prefix as two folders above pkgconfig/,
# which is wrong for Debian's multiarch libdir (lib/x86_64-linux-gnu) and gave
# -I<destdir>/usr/local/lib/include. Point prefix at the destdir copy instead.
json() { python3 -c "import json, sys; print($1)"; } # meson itself needs python3
prefix=$(meson introspect --buildoptions "$build" | json '[o["value"] for o in json.load(sys.stdin) if o["name"] == "prefix"][0]')
pcflags="--define-variable=prefix=$tmp/root$prefix"
flags=$(pkg-config $pcflags --cflags --libs lanecast)
echo "ok   pkg-config flags: $flags"
# a sanitized library needs its runtime in the program too (b_sanitize builds)
san=$(meson introspect --buildoptions "$build" | json '[o["value"] for o in json.load(sys.stdin) if o["name"] == "b_sanitize"][0]')
[ "$san" = none ] && san="" || san="-fsanitize=$san"
cc -std=c11 -Wall -Werror $san -o "$tmp/embed" "$src/examples/embed.c" $flags
libdir=$(pkg-config $pcflags --variable=libdir lanecast)
out=$(LD_LIBRARY_PATH="$libdir" LANECAST_TARGET=scalar "$tmp/embed")
echo "     embed printed: $out"
want="lanecast $(meson introspect --projectinfo "$build" | json 'json.load(sys.stdin)["version"]'), target scalar (1 lanes)
rendered 48x48, the volume is visible"
[ "$out" = "$want" ] || { echo "FAIL expected: $want"; exit 1; }
# the binary must use the installed library, not one from the build tree
LD_LIBRARY_PATH="$libdir" ldd "$tmp/embed" | grep -q "$libdir/liblanecast.so" || {
    echo "FAIL embed does not resolve liblanecast.so from $libdir"; exit 1; }
echo "PASS test_embed"
