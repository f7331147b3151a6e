#!/usr/bin/env bash
# Runs the libFuzzer target over grip's solvers for SECONDS (default 60), keeping its corpus in
# build/ci-fuzz/corpus. Build it first: cmake --workflow --preset ci-fuzz
# Usage: bash cmake/fuzz.sh [SECONDS]      e.g. bash cmake/fuzz.sh 1800 for 30 minutes
# A crash leaves its input as build/ci-fuzz/crash-*; replay it with
#   build/ci-fuzz/tests/grip_fuzz_solvers build/ci-fuzz/crash-<hash>
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-60}
mkdir -p build/ci-fuzz/corpus
cd build/ci-fuzz
exec ./tests/grip_fuzz_solvers -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 corpus
