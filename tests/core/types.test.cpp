// core/types.hpp: skew() and stable_norm() against hand-worked values.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <grip/core/types.hpp>

namespace types_test {

using namespace grip;

TEST_CASE("skew(r) v is the cross product r x v") {
  const Vector3<double> r(1, -2, 3), v(-4, 5, 0.5);
  // r x v by hand: (-2*0.5 - 3*5, 3*(-4) - 1*0.5, 1*5 - (-2)(-4)) = (-16, -12.5, -3).
  CHECK((skew(r) * v - Vector3<double>(-16, -12.5, -3)).norm() == 0.0);
}

TEST_CASE_TEMPLATE("stable_norm: 3-4-5 at every scale, where a sum of squares under- or overflows", S, float, double) {
  using L = std::numeric_limits<S>;
  const S dmin = L::denorm_min();
  // Denormal entries: 300 and 400 denormal steps are exact, their squares are 0.
  Wrench<S> tiny = Wrench<S>::Zero();
  tiny(1) = S(300) * dmin;
  tiny(4) = S(400) * dmin;
  CHECK(std::fabs(stable_norm(tiny) - S(500) * dmin) <= S(2) * dmin);
  // Normal but tiny: the squares underflow into the denormals and lose their digits.
  const S small = std::sqrt(L::min()) / S(1024);
  const Vector3<S> v2(S(3) * small, S(0), S(4) * small);
  CHECK(std::fabs(stable_norm(v2) / (S(5) * small) - S(1)) <= S(4) * L::epsilon());
  // Huge: the squares overflow.
  const S huge = std::sqrt(L::max());
  const Vector3<S> v3(S(3) * huge, S(4) * huge, S(0));
  CHECK(std::fabs(stable_norm(v3) / (S(5) * huge) - S(1)) <= S(4) * L::epsilon());
  // Ordinary values take the plain path and give the plain answer, bit for bit.
  const Vector3<S> v4(S(3), S(-4), S(12));
  CHECK(stable_norm(v4) == S(13));
  CHECK(stable_norm(Vector3<S>::Zero().eval()) == S(0));
  // Not finite stays not finite.
  CHECK(std::isnan(stable_norm(Vector3<S>(S(1), L::quiet_NaN(), S(0)))));
  CHECK(std::isinf(stable_norm(Vector3<S>(S(1), L::infinity(), S(0)))));
}

}  // namespace types_test
