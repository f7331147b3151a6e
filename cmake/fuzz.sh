#!/usr/bin/env bash
# Runs grip's libFuzzer targets for SECONDS in all (default 60), split between them: the
# solvers (grip_fuzz_solvers, corpus in build/ci-fuzz/corpus) and the mesh readers and distance
# field (grip_fuzz_mesh, corpus in build/ci-fuzz/corpus-mesh, seeded from tests/fuzz/corpus/mesh).
# The solvers' corpus is seeded from tests/fuzz/corpus/solvers (past findings among them).
# Build them first: cmake --workflow --preset ci-fuzz (this script builds any target missing).
# Usage: bash cmake/fuzz.sh [SECONDS]      e.g. bash cmake/fuzz.sh 1800 for 30 minutes
# A crash leaves its input as build/ci-fuzz/crash-*; replay it with
#   build/ci-fuzz/tests/grip_fuzz_solvers build/ci-fuzz/crash-<hash>   (or grip_fuzz_mesh)
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-60}
half=$(( secs / 2 > 0 ? secs / 2 : 1 ))
cmake --build build/ci-fuzz --target grip_fuzz_solvers grip_fuzz_mesh -j 2
mkdir -p build/ci-fuzz/corpus build/ci-fuzz/corpus-mesh
seeds=$PWD/tests/fuzz/corpus/mesh
solver_seeds=$PWD/tests/fuzz/corpus/solvers
cd build/ci-fuzz
status=0
./tests/grip_fuzz_solvers -max_total_time="$half" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 corpus "$solver_seeds" || status=$?
./tests/grip_fuzz_mesh -max_total_time="$(( secs - half > 0 ? secs - half : 1 ))" -timeout=10 -rss_limit_mb=2048 \
  -print_final_stats=1 corpus-mesh "$seeds" || status=$?
exit "$status"
