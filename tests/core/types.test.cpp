// core/types.hpp: skew(), detail::stable_norm(), detail::scale_symmetric() and the size helpers
// against hand-worked values;
// core/version.hpp: its spellings agree.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <grip/core/types.hpp>
#include <grip/core/version.hpp>

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
  CHECK(std::fabs(detail::stable_norm(tiny) - S(500) * dmin) <= S(2) * dmin);
  // Normal but tiny: the squares underflow into the denormals and lose their digits.
  const S small = std::sqrt(L::min()) / S(1024);
  const Vector3<S> v2(S(3) * small, S(0), S(4) * small);
  CHECK(std::fabs(detail::stable_norm(v2) / (S(5) * small) - S(1)) <= S(4) * L::epsilon());
  // Huge: the squares overflow.
  const S huge = std::sqrt(L::max());
  const Vector3<S> v3(S(3) * huge, S(4) * huge, S(0));
  CHECK(std::fabs(detail::stable_norm(v3) / (S(5) * huge) - S(1)) <= S(4) * L::epsilon());
  // Ordinary values take the plain path and give the plain answer, bit for bit.
  const Vector3<S> v4(S(3), S(-4), S(12));
  CHECK(detail::stable_norm(v4) == S(13));
  CHECK(detail::stable_norm(Vector3<S>::Zero().eval()) == S(0));
  // Not finite stays not finite.
  CHECK(std::isnan(detail::stable_norm(Vector3<S>(S(1), L::quiet_NaN(), S(0)))));
  CHECK(std::isinf(detail::stable_norm(Vector3<S>(S(1), L::infinity(), S(0)))));
}

TEST_CASE("times_or_dynamic and plus_or_dynamic: products and sums of sizes, Dynamic kept") {
  volatile int three = 3, dynamic = Dynamic;  // evaluated at run time as well as in constexpr uses
  CHECK(times_or_dynamic(three, 4) == 12);
  CHECK(times_or_dynamic(dynamic, 4) == Dynamic);
  CHECK(plus_or_dynamic(6, three * 3) == 15);  // the KKT size of three hard fingers: 6 + 3 n
  CHECK(plus_or_dynamic(6, dynamic) == Dynamic);
}

TEST_CASE_TEMPLATE("scale_symmetric: D a D in place, a hand-worked case and Eigen's products bit for bit", S, float,
                   double) {
  // A hand-worked entry: d = (1, 2, 3, 4, 5, 6), a(i, j) = i + 1 + 10 j: (D a D)(2, 5) = 3 * 53 * 6.
  Matrix6<S> a;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) a(i, j) = S(i + 1 + 10 * j);
  Wrench<S> d;
  d << S(1), S(2), S(3), S(4), S(5), S(6);
  Matrix6<S> b = a;
  detail::scale_symmetric(b, d);
  CHECK(b(2, 5) == S(3 * 53 * 6));
  CHECK(b(0, 0) == S(1));
  CHECK(b(5, 4) == S(6 * 46 * 5));
  // Entries whose products round: the same bits as d.asDiagonal() * a * d.asDiagonal().
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) a(i, j) = S(1) / S(3 + i + 7 * j);
  for (int k = 0; k < 6; ++k) d(k) = std::sqrt(S(2 + k));
  const Matrix6<S> ref = d.asDiagonal() * a * d.asDiagonal();
  detail::scale_symmetric(a, d);
  CHECK((a.array() == ref.array()).all());
}

TEST_CASE("version: the macros, the string literal and version() agree") {
  // Three spellings of the version are written by hand in version.hpp; a release that bumps one
  // must bump all.
  const Version v = version();
  char text[32];
  std::snprintf(text, sizeof text, "%d.%d.%d", v.major, v.minor, v.patch);
  CHECK(std::string(text) == GRIP_VERSION_STRING);
  CHECK(GRIP_VERSION == v.major * 10000 + v.minor * 100 + v.patch);
  CHECK(v.major == GRIP_VERSION_MAJOR);
  CHECK(v.minor == GRIP_VERSION_MINOR);
  CHECK(v.patch == GRIP_VERSION_PATCH);
}

}  // namespace types_test
