#!/usr/bin/env bash
# Builds examples/07_embedded/ for a Cortex-M4F with Debian's arm-none-eabi-g++ (freestanding
# style: -fno-exceptions -fno-rtti -DEIGEN_NO_MALLOC, -Os with EIGEN_UNROLLING_LIMIT=0 so that
# Eigen's fixed-size expressions stay loops, no linking), then checks:
#   1. every translation unit compiles, warnings as errors;
#   2. no object references malloc, free, calloc, realloc, operator new/delete or __cxa_throw;
#   3. grasp_step.o (solve_range_space + StabilityMonitor): .text < 16 KiB, worst-case stack
#      < 2.5 KiB (the deepest call chain from grip_grasp_step, frames summed: -fstack-usage
#      -fcallgraph-info=su, cmake/stack_depth.py; recursion or a dynamic frame fails);
#   4. constrained_step.o (solve_constrained + StabilityMonitor): .text < 29 888 B, stack < 6.5 KiB:
#      the interior-point method (its passes over the contacts, its driver and the lanes it keeps
#      on the stack) comes on top of the fast path and Newton's method (docs/testing.md).
# Usage: bash cmake/check_embedded.sh [build-dir]   (default build/embedded)
# Prints a figures table and "checks: N passed, M failed"; exits non-zero on any failure.
set -uo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/embedded}
mkdir -p "$out"
cxx=arm-none-eabi-g++
# The target and code flags (cmake/embedded.flags, shared with bench/m4_cycles.py), then this
# check's own: sections and stack use per function, warnings as errors.
read -r -d '' -a flags < cmake/embedded.flags
flags+=(-ffunction-sections -fdata-sections -fstack-usage -fcallgraph-info=su
        -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wdouble-promotion -Werror
        -Iinclude -isystem /usr/include/eigen3)
# Budgets per object: .text and worst-case stack, bytes.
declare -A code_budget=([grasp_step]=16384 [constrained_step]=29888)
declare -A stack_budget=([grasp_step]=2560 [constrained_step]=6656)
passed=0 failed=0
check() {  # check NAME CONDITION-EXIT-CODE
  if [ "$2" -eq 0 ]; then passed=$((passed + 1)); echo "  ok    $1"; else failed=$((failed + 1)); echo "  FAIL  $1"; fi
}
printf '%-22s %10s %14s %18s\n' object ".text (B)" "max frame (B)" "worst stack (B)"
for src in examples/07_embedded/*.cpp; do
  name=$(basename "$src" .cpp)
  rm -f "$out/$name.o" "$out/$name.su" "$out/$name.ci"
  if ! (cd "$out" && $cxx "${flags[@]/#-Iinclude/-I$OLDPWD/include}" -c "$OLDPWD/$src" -o "$name.o"); then
    check "$name compiles" 1
    continue
  fi
  check "$name compiles" 0
  bad=$(arm-none-eabi-nm -C "$out/$name.o" |
        grep -E ' (malloc|free|calloc|realloc|__cxa_throw|__cxa_allocate_exception)$|operator (new|delete)' || true)
  [ -z "$bad" ]; check "$name: no heap, no throw" $?
  [ -n "$bad" ] && echo "$bad"
  text=$(arm-none-eabi-size -A "$out/$name.o" | awk '$1 ~ /^\.text/ {s += $2} END {print s + 0}')
  su="$out/$name.su"
  maxf=$(awk -F'\t' '{if ($2 + 0 > m) m = $2 + 0} END {print m + 0}' "$su" 2>/dev/null || echo 0)
  root=$(arm-none-eabi-nm "$out/$name.o" | awk '$2 == "T" && $3 ~ /^grip_/ {print $3; exit}')
  if [ -z "$root" ]; then  # e.g. constrained_step before solve_constrained exists
    printf '%-22s %10s %14s %18s\n' "$name.o" "$text" "-" "(no entry point)"
    continue
  fi
  depth=$(python3 cmake/stack_depth.py "$out/$name.ci" "$root")
  stack_rc=$?
  worst=$(echo "$depth" | awk 'NR == 1 {print $1}')
  printf '%-22s %10s %14s %18s\n' "$name.o" "$text" "$maxf" "$worst"
  if [ -n "${code_budget[$name]:-}" ]; then
    [ "$text" -lt "${code_budget[$name]}" ]; check "$name: .text $text B < ${code_budget[$name]} B" $?
    [ "$stack_rc" -eq 0 ] && [ "${worst:-99999}" -lt "${stack_budget[$name]}" ]
    check "$name: stack $worst B < ${stack_budget[$name]} B" $?
  fi
  echo "$depth" | sed 's/^/  /'
  echo "  largest frames ($name, bytes):"
  sort -t$'\t' -k2,2nr "$su" | head -12 |
    awk -F'\t' '{n = $1; sub(/^[^:]*:[0-9]+:[0-9]+:/, "", n); printf "    %6d  %-8s %s\n", $2, $3, substr(n, 1, 110)}'
done
echo "checks: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
