# Sourced by tests/test_cli_mpi*.sh (after exe=LANECAST mpiexec=MPIEXEC):
# skips without mpiexec, makes $dir (removed on exit) and defines
# run K NAME EXT ARGS...: one process and K ranks render ARGS (default size
# 40x30) and the files must be the same bytes; sets fail=1 otherwise. With
# one_args set, the one process gets those arguments too.
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
    "$exe" render "$@" ${one_args:-} --threads 1 --quiet -o "$dir/one-$name.$ext" 2> "$dir/err1" || true
    if timeout 60 "$mpiexec" --oversubscribe -np "$k" "$exe" render "$@" --threads 1 --quiet \
        -o "$dir/np$k-$name.$ext" 2> "$dir/err" && cmp -s "$dir/one-$name.$ext" "$dir/np$k-$name.$ext"; then
        echo "ok   np $k $name"
    else
        echo "FAIL np $k $name: $(cat "$dir/err1" "$dir/err")"
        fail=1
    fi
}
