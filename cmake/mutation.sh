#!/usr/bin/env bash
# Mutation run: applies deliberate faults to the library one at a time, builds the tests that
# mirror the faulty header (clang++ -O0, unity, -march=native so that the SIMD kernels of this
# CPU are the ones compiled and run), runs them, and reports which fault the suite caught.
# Exits non-zero when any fault survives (or a fault no longer applies: its text is gone).
#   bash cmake/mutation.sh              every fault
#   bash cmake/mutation.sh sign tail    only the faults named
# The faults go into a copy of the source tree (build/mutation-src), never into the tree
# itself, so other builds may run beside it. Builds go to build/mutation-src/build/<name>; a
# fault's log to build/mutation-<name>.log.
set -uo pipefail
cd "$(dirname "$0")/.."
root=$PWD
src=$root/build/mutation-src
rm -rf "$src" && mkdir -p "$src"
tar --exclude=./build --exclude=./.git -cf - . | tar -xf - -C "$src"

# name | file | text to replace (must occur) | replacement | test files (regex on tests/ paths)
faults=$(cat <<'EOF'
sign|include/grip/contact/contact_model.hpp|    w(3) = ry * f.z() - rz * f.y();|    w(3) = rz * f.y() - ry * f.z();|grasp/grasp
radius|include/grip/contact/coulomb_cone.hpp|return CoulombCone{c.normal, c.friction};|return CoulombCone{c.normal, c.friction * Scalar(1.1)};|contact/coulomb_cone
projection|include/grip/solve/detail/constrained_passes.hpp|  return keep * v + sb * a + bb * ftv;|  return v + S(0) * (keep * v + sb * a + bb * ftv);|solve/solve_constrained\.
tail|include/grip/contact/coulomb_kernel.hpp|x + 3 * b, n - b|x + 3 * b, n - b - (n - b > 1 ? 1 : 0)|contact/coulomb_kernel|core/simd
jacobian|include/grip/solve/projection_jacobian.hpp|  j.noalias() += beta * (Matrix3<Scalar>::Identity() - a * a.transpose() - e * e.transpose());|  j.noalias() += beta * (Matrix3<Scalar>::Identity() - a * a.transpose());|solve/projection_jacobian|contact/coulomb_cone
pipeline|include/grip/pipeline/haptic_stages.hpp|        const auto i = detail::idx(index_[detail::idx(j)]);|        const auto i = detail::idx(index_[detail::idx(j < 2 && grasp_.size() > 1 ? 1 - j : j)]);|pipeline/haptic_pipeline
horizon|include/grip/analysis/detail/epsilon_polytope.hpp|            m = mg > threshold ? S(sees) : S(seen);|            m = mg > threshold + threshold ? S(sees) : S(seen);|analysis/epsilon
corrector|include/grip/solve/detail/cone_packs.hpp|  for (int r = 1; r < D; ++r) ld = neg_mul_add(l[r], d[r], ld);|  for (int r = 1; r < D; ++r) ld = mul_add(l[r], d[r], ld);|solve/cone_packs|analysis/conic_reference
lipschitz|include/grip/collision/detail/narrow_phase.hpp|if (!(below - spacing > -band) && may_be_inside(x))|if (!(below + spacing > -band) && may_be_inside(x))|collision/collision_bounds
EOF
)

restore() { [ -n "${current:-}" ] && cp "$root/$current" "$src/$current"; current=""; }

caught=() survived=()
while IFS='|' read -r name file old new tests; do
  [ -z "$name" ] && continue
  if [ $# -gt 0 ] && ! printf '%s\n' "$@" | grep -qx "$name"; then continue; fi
  log=$root/build/mutation-$name.log
  if ! grep -qF -- "$old" "$src/$file"; then
    echo "fault $name: its text is no longer in $file" | tee "$log"
    survived+=("$name (stale)")
    continue
  fi
  current=$file
  OLD=$old NEW=$new python3 - "$src/$file" <<'PY'
import os, sys
p = sys.argv[1]
s = open(p).read()
open(p, 'w').write(s.replace(os.environ['OLD'], os.environ['NEW']))
PY
  s=$(date +%s)
  (
    cd "$src" &&
      cmake --preset test -B "build/$name" -DGRIP_TEST_ONLY="$tests" -DGRIP_BUILD_EXAMPLES=OFF \
        -DGRIP_UNITY_GROUPS=1 -DCMAKE_CXX_FLAGS=-march=native &&
      cmake --build "build/$name" -j 2 &&
      ctest --test-dir "build/$name" -j 2 --output-on-failure --stop-on-failure
  ) > "$log" 2>&1
  rc=$?
  restore
  if grep -qE 'error:' "$log"; then
    verdict="does not compile"
    survived+=("$name (does not compile)")
  elif [ "$rc" -ne 0 ]; then
    verdict="caught ($(grep -cE '\*\*\*Failed' "$log") tests failed)"
    caught+=("$name")
  else
    verdict="SURVIVED"
    survived+=("$name")
  fi
  printf 'fault %-10s %-44s %4s s  %s\n' "$name" "$file" "$(($(date +%s) - s))" "$verdict"
done <<< "$faults"

echo "mutation: ${#caught[@]} caught, ${#survived[@]} survived${survived:+: ${survived[*]}}"
[ "${#survived[@]}" -eq 0 ]
