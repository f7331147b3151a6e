#pragma once
// The solver fuzz target's input format, shared by grip_fuzz_solvers (fuzz_solvers.cpp) and
// the doctest replay of its findings (tests/hostile/fuzz_findings.test.cpp): the bytes decode
// into a grasp (model, size, raw float/double fields: any bit pattern, so NaN, Inf, denormals
// and huge values all occur) and an external wrench; every solver then runs under the oracle
// of the hostile-input test (tests/hostile/oracle.hpp).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "hostile/oracle.hpp"

namespace grip_fuzz {

/// Reads the fuzzer's bytes front to back; zeros once they run out.
class Bytes {
 public:
  Bytes(const std::uint8_t* p, std::size_t n) : p_(p), n_(n) {}
  template <class T>
  T get() {
    T v{};
    unsigned char buf[sizeof(T)] = {};
    const std::size_t k = n_ < sizeof(T) ? n_ : sizeof(T);
    if (k > 0) std::memcpy(buf, p_, k);
    p_ += k;
    n_ -= k;
    std::memcpy(&v, buf, sizeof(T));
    return v;
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_;
};

/// A field: either raw bits (anything) or, when the selector byte says so, a tame value
/// (so that valid grasps, which reach the numerical code, are common).
template <class S>
S field(Bytes& b, S tame) {
  const std::uint8_t sel = b.get<std::uint8_t>();
  const S raw = b.get<S>();
  return sel < 160 ? tame + S(0.01f) * S(static_cast<std::int8_t>(sel)) / S(128) : raw;
}

/// Builds one grasp of type GraspT and a wrench from b and checks every solver on them:
/// nullptr when all keep their contracts, else what broke. With EIGEN_RUNTIME_NO_MALLOC
/// defined, Eigen's heap check is armed around the solvers.
template <class GraspT>
const char* run(Bytes& b) {
  using S = typename GraspT::ScalarType;
  GraspT g;
  grip_hostile::Expect e;
  const int n = GraspT::fixed_size == grip::Dynamic ? 1 + b.get<std::uint8_t>() % GraspT::capacity : g.size();
  for (int i = 0; i < n; ++i) {
    grip::Contact<S> c;
    const S angle = S(2.4f) * S(i);
    for (int k = 0; k < 3; ++k)
      c.position(k) = field<S>(b, S(0.03f) * (k == 0 ? std::cos(angle) : k == 1 ? std::sin(angle) : S(0)));
    for (int k = 0; k < 3; ++k) c.normal(k) = field<S>(b, k == 0 ? -std::cos(angle) : k == 1 ? -std::sin(angle) : S(0));
    if (b.get<std::uint8_t>() < 200 && c.normal.allFinite() && c.normal.norm() > S(0)) c.normal.normalize();
    c.friction = field<S>(b, S(0.5f));
    c.torsional_friction = field<S>(b, S(0.01f));
    c.squeeze = field<S>(b, S(1));
    c.weight = field<S>(b, S(1));
    const grip::Status st = GraspT::fixed_size == grip::Dynamic ? g.add(c) : g.set(i, c);
    // At the normal's tolerance edge the verdict is the library's rounding (either is right).
    const bool valid =
        grip_hostile::normal_on_tolerance_edge(c) ? st == grip::Status::Ok : grip_hostile::contact_valid(c);
    if ((st == grip::Status::Ok) != valid) return "Grasp::set/add disagrees with the oracle";
    if (!valid && GraspT::fixed_size != grip::Dynamic) e.contacts_valid = false;
  }
  grip::Wrench<S> w;
  for (int k = 0; k < 6; ++k) w(k) = field<S>(b, S(0));
#ifdef EIGEN_RUNTIME_NO_MALLOC
  Eigen::internal::set_is_malloc_allowed(false);
#endif
  const char* msg = grip_hostile::check_solvers(g, w, e);
#ifdef EIGEN_RUNTIME_NO_MALLOC
  Eigen::internal::set_is_malloc_allowed(true);
#endif
  return msg;
}

/// The whole input: its first byte picks the grasp type.
inline const char* check_solver_input(const std::uint8_t* data, std::size_t size) {
  Bytes b(data, size);
  switch (b.get<std::uint8_t>() % 8) {
    case 0: return run<grip::Grasp<3, grip::HardFinger, double>>(b);
    case 1: return run<grip::Grasp<3, grip::HardFinger, float>>(b);
    case 2: return run<grip::Grasp<grip::Dynamic, grip::HardFinger, double, 6>>(b);
    case 3: return run<grip::Grasp<grip::Dynamic, grip::HardFinger, float, 6>>(b);
    case 4: return run<grip::Grasp<4, grip::SoftFinger, double>>(b);
    case 5: return run<grip::Grasp<grip::Dynamic, grip::SoftFinger, float, 5>>(b);
    case 6: return run<grip::Grasp<grip::Dynamic, grip::FrictionlessPoint, double, 8>>(b);
    default: return run<grip::Grasp<7, grip::FrictionlessPoint, float>>(b);
  }
}

/// True for a message that breaks a promise.
inline bool broken(const char* msg) { return msg != nullptr; }

}  // namespace grip_fuzz
