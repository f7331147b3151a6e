#!/usr/bin/env bash
# Line coverage of include/grip by the whole suite, and the suite's run under AddressSanitizer
# and UndefinedBehaviorSanitizer, in one build: the ci-sanitize preset (clang++ -O0, source-based
# coverage: -fprofile-instr-generate -fcoverage-mapping) builds the suite and the examples and
# runs them, then llvm-cov (Debian's llvm) writes
#   build/ci-sanitize/coverage/report.txt     per header: lines, lines missed, percent covered
#   build/ci-sanitize/coverage/uncovered.txt  per header, the line numbers that no test executed
#   build/ci-sanitize/coverage/unexecuted_functions.txt  the functions that no test executed
# and both are printed. Exits non-zero when the build or a test fails.
# Usage: bash cmake/coverage.sh            (needs clang and llvm-cov / llvm-profdata)
set -euo pipefail
cd "$(dirname "$0")/.."
build=build/ci-sanitize
dir=$build/coverage
rm -rf "$dir" && mkdir -p "$dir"
cmake --preset ci-sanitize
# Two compilers at a time (the ci-sanitize build preset), over six unity groups rather than the
# suite's four: an instrumented group of a quarter of the suite reached 8.5 GB, and .ci/run builds
# another configuration alongside (two of those and armhf's four compilers overflowed 24 GB).
cmake --build --preset ci-sanitize
# Only the test run's profiles count (the build runs the binary once to list its tests).
rm -rf "$build/profiles"
ctest --preset ci-sanitize
tool() { command -v "$1" || command -v "$1-14"; }
"$(tool llvm-profdata)" merge -sparse "$build"/profiles/*.profraw -o "$dir/grip.profdata"
bin=$build/tests/grip_tests
"$(tool llvm-cov)" report "$bin" -instr-profile="$dir/grip.profdata" "$PWD/include" > "$dir/llvm-report.txt"
# Per header: lines and missed lines from llvm-cov's table (columns: file, regions, missed,
# cover, functions, missed, executed, lines, missed, cover, ...; file names relative to
# include/grip, their common prefix).
awk '$1 ~ /\.hpp$/ {printf "%-50s %6s %6s %8s\n", "include/grip/" $1, $8, $9, $10}
     $1 == "TOTAL" {total = sprintf("%-50s %6s %6s %8s", "TOTAL", $8, $9, $10)}
     END {print total}' "$dir/llvm-report.txt" | sort > "$dir/report.txt"
# The uncovered lines, from the annotated source: "  line|  count|source", count 0.
"$(tool llvm-cov)" show "$bin" -instr-profile="$dir/grip.profdata" "$PWD/include" -show-line-counts \
  -use-color=false |
  awk -F'|' '/^\/.*\.hpp:$/ {file = $0; sub(/:$/, "", file); sub(/.*include\//, "include/", file); next}
             NF >= 3 && $2 ~ /^ *0 *$/ {gsub(/ /, "", $1); miss[file] = miss[file] " " $1}
             END {for (f in miss) print f ":" miss[f]}' | sort > "$dir/uncovered.txt"
# The functions that no test executed (any instantiation counts).
"$(tool llvm-cov)" export "$bin" -instr-profile="$dir/grip.profdata" "$PWD/include" -skip-expansions |
  python3 cmake/unexecuted_functions.py > "$dir/unexecuted_functions.txt"
echo "== line coverage of include/grip (lines, missed, covered) =="
cat "$dir/report.txt"
echo "== uncovered lines per header =="
cat "$dir/uncovered.txt"
echo "== functions never executed =="
cat "$dir/unexecuted_functions.txt"
