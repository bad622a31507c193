# Sourced by tests/test_cli_mpi*.sh (after exe=LANECAST mpiexec=MPIEXEC):
# skips without mpiexec, makes $dir (removed on exit) and defines
# run K NAME EXT ARGS...: one process and K ranks render ARGS (default size
# 40x30) and the files must be the same bytes; sets fail=1 otherwise.
# bits NAME KS ARGS...: one process renders ARGS (40x30, --alpha-stop 1) once
# as a float EXR with its defaults (the canonical BVH), mpiexec -np K for
# each K in KS too, and each K's image must be the one process's exactly
# (view_imgcmp exact, $imgcmp), or with near=D set within D 8-bit steps.
if [ -z "$mpiexec" ]; then
    echo "mpiexec not found (Debian: openmpi-bin): skipped"
    exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
run() {
    k=$1 name=$2 ext=$3
    shift 3
    set -- --size 40x30 "$@"
    "$exe" render "$@" --threads 1 --quiet -o "$dir/one-$name.$ext" 2> "$dir/err1" || true
    if timeout 60 "$mpiexec" --oversubscribe -np "$k" "$exe" render "$@" --threads 1 --quiet \
        -o "$dir/np$k-$name.$ext" 2> "$dir/err" && cmp -s "$dir/one-$name.$ext" "$dir/np$k-$name.$ext"; then
        echo "ok   np $k $name"
    else
        echo "FAIL np $k $name: $(cat "$dir/err1" "$dir/err")"
        fail=1
    fi
}
bits() {
    name=$1 ks=$2
    shift 2
    set -- --size 40x30 --alpha-stop 1 "$@"
    how=exact
    [ -n "${near:-}" ] && how="max=$near"
    "$exe" render "$@" --threads 1 --quiet -o "$dir/one-$name.exr" 2> "$dir/err1" || true
    for k in $ks; do
        if timeout 60 "$mpiexec" --oversubscribe -np "$k" "$exe" render "$@" --threads 1 --quiet \
            -o "$dir/np$k-$name.exr" 2> "$dir/err" &&
            "$imgcmp" "$dir/np$k-$name.exr" "$dir/one-$name.exr" "$how" > "$dir/cmp" 2>&1; then
            echo "ok   np $k $name ($how)"
        else
            echo "FAIL np $k $name ($how): $(cat "$dir/cmp" "$dir/err1" "$dir/err" 2>/dev/null)"
            fail=1
        fi
    done
}
