// libFuzzer target over grip's public solvers (clang -fsanitize=fuzzer,address,undefined).
// The bytes decode into a grasp (model, size, raw float/double fields: any bit pattern, so
// NaN, Inf, denormals and huge values all occur) and an external wrench; every solver then
// runs under the same oracle as the hostile-input test (tests/hostile/oracle.hpp), with
// Eigen's heap check armed. Any broken promise aborts, which libFuzzer reports as a crash.
//
// Build and run (N minutes = 60 N seconds), from the source tree:
//   cmake --workflow --preset ci-fuzz && bash cmake/fuzz.sh 600
#define EIGEN_RUNTIME_NO_MALLOC
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "hostile/oracle.hpp"

namespace {

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

template <class GraspT>
void run(Bytes& b) {
  using S = typename GraspT::ScalarType;
  GraspT g;
  grip_hostile::Expect e;
  const int n = GraspT::fixed_size == grip::Dynamic ? 1 + b.get<std::uint8_t>() % GraspT::capacity : g.size();
  for (int i = 0; i < n; ++i) {
    grip::Contact<S> c;
    const S angle = S(2.4f) * S(i);
    for (int k = 0; k < 3; ++k) c.position(k) = field<S>(b, S(0.03f) * (k == 0 ? std::cos(angle) : k == 1 ? std::sin(angle) : S(0)));
    for (int k = 0; k < 3; ++k) c.normal(k) = field<S>(b, k == 0 ? -std::cos(angle) : k == 1 ? -std::sin(angle) : S(0));
    if (b.get<std::uint8_t>() < 200 && c.normal.allFinite() && c.normal.norm() > S(0)) c.normal.normalize();
    c.friction = field<S>(b, S(0.5f));
    c.torsional_friction = field<S>(b, S(0.01f));
    c.squeeze = field<S>(b, S(1));
    c.weight = field<S>(b, S(1));
    const bool valid = grip_hostile::contact_valid(c);
    const grip::Status st = GraspT::fixed_size == grip::Dynamic ? g.add(c) : g.set(i, c);
    if ((st == grip::Status::Ok) != valid) {
      std::fprintf(stderr, "Grasp::set/add disagrees with the oracle\n");
      std::abort();
    }
    if (!valid && GraspT::fixed_size != grip::Dynamic) e.contacts_valid = false;
  }
  grip::Wrench<S> w;
  for (int k = 0; k < 6; ++k) w(k) = field<S>(b, S(0));
  e.moderate_scale = false;  // arbitrary magnitudes: the least-squares bound is "soft"
  Eigen::internal::set_is_malloc_allowed(false);
  const char* msg = grip_hostile::check_solvers(g, w, e);
  Eigen::internal::set_is_malloc_allowed(true);
  if (msg && std::strncmp(msg, "soft:", 5) != 0) {
    std::fprintf(stderr, "broken promise: %s\n", msg);
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes b(data, size);
  switch (b.get<std::uint8_t>() % 8) {
    case 0: run<grip::Grasp<3, grip::HardFinger, double>>(b); break;
    case 1: run<grip::Grasp<3, grip::HardFinger, float>>(b); break;
    case 2: run<grip::Grasp<grip::Dynamic, grip::HardFinger, double, 6>>(b); break;
    case 3: run<grip::Grasp<grip::Dynamic, grip::HardFinger, float, 6>>(b); break;
    case 4: run<grip::Grasp<4, grip::SoftFinger, double>>(b); break;
    case 5: run<grip::Grasp<grip::Dynamic, grip::SoftFinger, float, 5>>(b); break;
    case 6: run<grip::Grasp<grip::Dynamic, grip::FrictionlessPoint, double, 8>>(b); break;
    default: run<grip::Grasp<7, grip::FrictionlessPoint, float>>(b); break;
  }
  return 0;
}
