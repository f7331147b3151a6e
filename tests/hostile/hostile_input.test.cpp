// Hostile input: seeded random and adversarial grasps thrown at every public solver, the
// monitor and the resolution step (solve_constrained on 1 grasp in 8) (see
// oracle.hpp for what is checked: status matches the input, outputs finite, least squares
// no worse than doing nothing, Ok answers accurate) with no heap and no crash.
//
// Size: GRIP_HOSTILE_COUNT grasps in all (half float, half double), default 20000; the full
// million: GRIP_HOSTILE_COUNT=1000000 ./build/<preset>/tests/grip_tests -tc='hostile*'
// GRIP_HOSTILE_SEED shifts the seeds; a failure prints the seed that reproduces it.
#include <doctest/doctest.h>

#include <cstdlib>
#include <limits>
#include <map>
#include <random>
#include <string>

#include "hostile/oracle.hpp"
#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"

using namespace grip;
using grip_hostile::Expect;

namespace {

long env_long(const char* name, long fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::strtol(v, nullptr, 10) : fallback;
}

/// One adversarial value: NaN, infinities, denormals, zeros, huge and tiny magnitudes,
/// the max_magnitude limit and just beyond it, negative numbers.
template <class S>
S hostile_value(std::mt19937& rng) {
  using L = std::numeric_limits<S>;
  const S big = ScalarTraits<S>::max_magnitude;
  const S values[] = {L::quiet_NaN(),
                      L::infinity(),
                      -L::infinity(),
                      L::denorm_min(),
                      -L::denorm_min(),
                      L::min() / S(4),
                      S(0),
                      -S(0),
                      S(1e-30f),
                      -S(1e-30f),
                      S(1e12f),
                      -S(1e12f),
                      big,
                      -big,
                      std::nextafter(big, L::infinity()),
                      L::max(),
                      L::lowest(),
                      S(-1),
                      S(-1e-6f)};
  return values[grip_test::UniformInt(0, int(sizeof(values) / sizeof(S)) - 1)(rng)];
}

/// A valid random contact, then (with probability p per field) one field made hostile.
template <class S>
Contact<S> mutate(std::mt19937& rng, Contact<S> c, double p) {
  grip_test::Uniform u(0.0, 1.0);
  const S tol = ScalarTraits<S>::normal_tolerance;
  for (int k = 0; k < 3; ++k)
    if (u(rng) < p) c.position(k) = hostile_value<S>(rng);
  if (u(rng) < p) c.normal(grip_test::UniformInt(0, 2)(rng)) = hostile_value<S>(rng);
  if (u(rng) < p) {
    switch (grip_test::UniformInt(0, 4)(rng)) {
      case 0: c.normal.setZero(); break;             // zero normal
      case 1: c.normal *= S(2); break;               // non-unit
      case 2: c.normal *= S(1) + S(8) * tol; break;  // just non-unit
      case 3: c.normal *= S(1) + tol / S(4); break;  // unit within tolerance
      default: c.normal = -c.normal; break;          // pulling: still unit
    }
  }
  if (u(rng) < p) c.friction = u(rng) < 0.5 ? S(0) : hostile_value<S>(rng);  // mu = 0 is valid
  if (u(rng) < p) c.torsional_friction = hostile_value<S>(rng);
  if (u(rng) < p) c.squeeze = u(rng) < 0.5 ? -S(1) : hostile_value<S>(rng);  // negative squeeze
  if (u(rng) < p) c.weight = u(rng) < 0.5 ? ScalarTraits<S>::min_weight : hostile_value<S>(rng);
  return c;
}

/// A random unit vector.
template <class S>
Vector3<S> unit(std::mt19937& rng) {
  return grip_test::sphere_contact<S>(std::acos(grip_test::Uniform(-1, 1)(rng)),
                                      grip_test::Uniform(0, 6.283185307179586)(rng), 1.0)
      .normal;
}

/// A wrench: random (a few N), of 1e12 N, or with one hostile component.
template <class S>
Wrench<S> make_wrench(std::mt19937& rng, int kind) {
  Wrench<S> w = grip_test::random_wrench<S>(rng);
  if (kind == 1) w = (w.template cast<double>() * 2e11).template cast<S>();  // |F| ~ 1e12 N
  if (kind == 2) w(grip_test::UniformInt(0, 5)(rng)) = hostile_value<S>(rng);
  return w;
}

/// Builds one adversarial grasp of type GraspT (category `cat`), runs every solver on it
/// inside a NoHeapScope, and returns nullptr or the broken promise.
template <class GraspT>
const char* trial(std::mt19937& rng, int cat, long& heap) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  grip_test::Uniform u(0.0, 1.0);
  constexpr bool fixed = GraspT::fixed_size != Dynamic;
  const int n = fixed ? GraspT::capacity : grip_test::UniformInt(1, GraspT::capacity)(rng);
  const int full_rank_n = std::is_same<M, FrictionlessPoint>::value ? 6 : 3;
  Expect e;
  Contact<S> cs[GraspT::capacity];
  const Vector3<S> axis_dirs[] = {Vector3<S>(S(1), S(0), S(0)), Vector3<S>(S(0), S(1), S(0)),
                                  Vector3<S>(S(1), S(1), S(0)), Vector3<S>(S(1), S(-1), S(1))};
  const Vector3<S> dir = axis_dirs[grip_test::UniformInt(0, 3)(rng)];
  const Vector3<S> offset(S(grip_test::UniformInt(-4, 4)(rng)) / S(64), S(grip_test::UniformInt(-4, 4)(rng)) / S(64),
                          S(0));
  for (int i = 0; i < n; ++i) {
    Contact<S> c = grip_test::random_contact<S>(rng);
    switch (cat) {
      case 0: break;                            // clean
      case 1: c = mutate(rng, c, 0.08); break;  // hostile fields
      case 2:                                   // exactly collinear (dyadic points)
        c.position = offset + S(grip_test::UniformInt(-8, 8)(rng)) / S(128) * dir;
        c.normal = unit<S>(rng);
        break;
      case 3:
        c = cs[0];
        if (i == 0) c = grip_test::random_contact<S>(rng);
        break;   // duplicated
      case 4: {  // tiny or huge but valid scales
        // Huge but valid: three orders below the largest accepted coordinate
        // (ScalarTraits<S>::max_magnitude: 1e12 in double, 1e6 in float). Not a tolerance.
        const double s = u(rng) < 0.5 ? 1e-6 : 1e-3 * double(ScalarTraits<S>::max_magnitude);
        c.position = (c.position.template cast<double>() * s).template cast<S>();
        c.squeeze = S(double(c.squeeze) * (u(rng) < 0.5 ? 1e-20 : 1e6));
        c.weight = u(rng) < 0.5 ? ScalarTraits<S>::min_weight : c.weight;
        break;
      }
      default: c = mutate(rng, c, 0.02); break;  // mostly valid, hostile wrench below
    }
    cs[i] = c;
  }
  if (cat == 3) cs[0] = cs[n > 1 ? 1 : 0];
  GraspT g;
  for (int i = 0; i < n; ++i) {
    const bool valid = grip_hostile::contact_valid(cs[i]);
    const Status st = fixed ? g.set(i, cs[i]) : g.add(cs[i]);
    if ((st == Status::Ok) != valid) return "Grasp::set/add disagrees with the validity of the contact";
    if ((validate(cs[i]) == Status::Ok) != valid) return "validate() disagrees with the oracle";
    if (!valid) e.contacts_valid = fixed ? false : e.contacts_valid;  // Dynamic: contact not added
  }
  if (!fixed && g.size() == 0) {  // an empty Dynamic grasp: valid input, rank 0
    e.must_be_singular = true;
  }
  const bool all_valid = e.contacts_valid && g.size() == n;
  if (cat == 2 || cat == 3) e.must_be_singular = !std::is_same<M, SoftFinger>::value || cat == 3;
  if (g.size() < full_rank_n && !std::is_same<M, SoftFinger>::value) e.must_be_singular = true;
  if (std::is_same<M, SoftFinger>::value && g.size() == 1) e.must_be_singular = true;
  e.well_conditioned = cat == 0 && all_valid && g.size() >= 3 && !std::is_same<M, FrictionlessPoint>::value;
  const Wrench<S> w = make_wrench<S>(rng, cat >= 5 ? grip_test::UniformInt(0, 2)(rng) : 0);
  if (!grip_hostile::wrench_valid(w)) e.well_conditioned = false;
  const bool with_constrained = u(rng) < 0.125;  // 1 in 8: the iterative solver dominates the time
  const char* msg = nullptr;
  {
    grip_test::NoHeapScope scope;
    msg = grip_hostile::check_solvers(g, w, e, with_constrained);
    if (msg == nullptr && g.unknowns() > 0) {  // the monitor on forces with a hostile entry
      typename GraspT::ForceVector x = solve_range_space(g, w).forces;
      x(grip_test::UniformInt(0, g.unknowns() - 1)(rng)) = hostile_value<S>(rng);
      msg = grip_hostile::check_monitor(g, x, w);
    }
    heap += scope.allocations();
  }
  return msg;
}

template <class S>
const char* one(std::mt19937& rng, long& heap) {
  const int cat = grip_test::UniformInt(0, 6)(rng);
  switch (grip_test::UniformInt(0, 3)(rng)) {  // fixed and Dynamic, each model
    case 0: return trial<Grasp<3, HardFinger, S>>(rng, cat, heap);
    case 1: return trial<Grasp<Dynamic, HardFinger, S, 8>>(rng, cat, heap);
    case 2: return trial<Grasp<4, SoftFinger, S>>(rng, cat, heap);
    default: return trial<Grasp<Dynamic, FrictionlessPoint, S, 8>>(rng, cat, heap);
  }
}

}  // namespace

TEST_CASE_TEMPLATE("hostile input: every solver keeps its contract on adversarial grasps", S, double, float) {
  const long count = env_long("GRIP_HOSTILE_COUNT", 20000) / 2;
  const long base = env_long("GRIP_HOSTILE_SEED", 0);
  const unsigned long offset = std::is_same<S, float>::value ? 0x9e3779b9ul : 0ul;  // float: other seeds
  long heap = 0;
  std::map<std::string, std::pair<long, long>> broken;  // message -> (count, first GRIP_HOSTILE_SEED)
  for (long i = 0; i < count; ++i) {
    std::mt19937 rng(static_cast<std::mt19937::result_type>(static_cast<unsigned long>(base + i) + offset));
    if (const char* msg = one<S>(rng, heap)) {
      auto& b = broken[msg];
      if (b.first++ == 0) b.second = base + i;
    }
  }
  long failures = 0;
  for (const auto& [msg, b] : broken) {
    failures += b.first;
    const std::string line = msg + ": " + std::to_string(b.first) + " of " + std::to_string(count) +
                             " grasps; first: GRIP_HOSTILE_SEED=" + std::to_string(b.second) + " GRIP_HOSTILE_COUNT=2";
    FAIL_CHECK(line);
  }
  CHECK(failures == 0);
  CHECK(heap == 0);
}
