#!/usr/bin/env bash
# Line coverage of include/grip by the whole suite: clang++ -O0 with source-based coverage
# (-fprofile-instr-generate -fcoverage-mapping, Debian's llvm), every test run, then
#   build/coverage/report.txt     per header: lines, lines missed, percent covered
#   build/coverage/uncovered.txt  per header, the line numbers that no test executed
# and both printed. Exits non-zero only when the build or a test fails.
# Usage: bash cmake/coverage.sh            (needs clang and llvm-cov / llvm-profdata)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=build/coverage
flags="-fprofile-instr-generate -fcoverage-mapping"
# -O0 (the test preset's): with coverage mapping, -O1 builds the unity sources several times
# slower than the suite then saves in running.
cmake --preset test -B "$dir" -DGRIP_BUILD_EXAMPLES=OFF -DGRIP_WARNINGS_AS_ERRORS=ON -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fprofile-instr-generate"
cmake --build "$dir" -j 2
rm -rf "$dir/profiles" && mkdir -p "$dir/profiles"
GRIP_HOSTILE_COUNT=4000 LLVM_PROFILE_FILE="$PWD/$dir/profiles/%p.profraw" ctest --test-dir "$dir" -j 2
tool() { command -v "$1" || command -v "$1-14"; }
"$(tool llvm-profdata)" merge -sparse "$dir"/profiles/*.profraw -o "$dir/grip.profdata"
bin=$dir/tests/grip_tests
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
echo "== line coverage of include/grip (lines, missed, covered) =="
cat "$dir/report.txt"
echo "== uncovered lines per header =="
cat "$dir/uncovered.txt"
