#!/bin/sh
# The concurrency test (tests/test_concurrency.c: one shared scene of each
# kind rendered from several threads at once, each with its own device) and
# the per-volume caches (host/api/vcache.c: mutex and references):
# tests/test_grid_tables.c (two threads on one volume with alternating TFs)
# and tests/test_particles_cstep.c (two threads alternating the step)
# under ThreadSanitizer, in ./build-tsan. Any report fails (halt_on_error).
# Embree and TBB (the BVH builds, before the threads start) are not
# instrumented: TSan cannot see their internal synchronisation, so reports
# whose stacks pass through them are suppressed (scripts/tsan.supp); races
# in lanecast's own code are not. Render jobs (tests/test_render_job.c:
# threads of their own, cancels, overlapping and destroyed jobs) run too.
# usage: scripts/tsan.sh [WORKERS]   (default 4)
set -eu
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
b=build-tsan
if [ ! -f $b/build.ninja ]; then
    meson setup $b --buildtype=debugoptimized -Db_sanitize=thread -Db_lundef=false -Dwerror=true >/dev/null
fi
ninja -C $b tests/test_concurrency tests/test_grid_tables tests/test_particles_cstep tests/test_render_job >/dev/null
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1"
# ASLR with a high entropy breaks TSan's memory layout on newer kernels: run without it when possible
run=""
setarch "$(uname -m)" -R true 2>/dev/null && run="setarch $(uname -m) -R"
$run $b/tests/test_concurrency "${1:-4}"
$run $b/tests/test_grid_tables "$b/tests"
$run $b/tests/test_particles_cstep
$run $b/tests/test_render_job 60
echo "tsan.sh: no data race reported" >&2
