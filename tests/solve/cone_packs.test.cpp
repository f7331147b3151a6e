// The second-order cone's algebra on SIMD packs (solve/detail/cone_packs.hpp, what the
// interior-point method's passes compute with), lane by lane against the scalar definitions of
// tests/support/second_order_cone.hpp: the Nesterov-Todd scaling by its defining identities,
// the Jordan product and division, and the step to the cone's boundary against bisection on
// membership. For the pack this translation unit compiles, the 4-lane pack where AVX2 is
// compiled, and the scalar packs of double and float; for cone counts that leave the last pack
// partly filled with the cones' centre e, as the interior-point lanes pad it.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <grip/solve/detail/cone_packs.hpp>

#include "support/random.hpp"
#include "support/second_order_cone.hpp"
#include "support/tolerance.hpp"

using namespace grip;

namespace {

template <int D>
using Ref = grip_test::SocVector<double, D>;

// A random point of the interior of Q^D: the tail drawn in a ball, the head above its norm.
template <int D>
Ref<D> interior(std::mt19937& rng) {
  grip_test::Uniform u(-1.0, 1.0), lift(0.01, 2.0);
  Ref<D> v;
  for (int k = 0; k < D; ++k) v(k) = u(rng);
  v(0) = grip_test::soc_tail_norm(v) + lift(rng);
  return v;
}

// Membership of u + a d in the interior of Q, in long double (11 more bits than double).
template <int D>
bool inside_long(const Ref<D>& u, const Ref<D>& d, long double a) {
  long double head = static_cast<long double>(u(0)) + a * static_cast<long double>(d(0)), tail = 0;
  for (int k = 1; k < D; ++k) {
    const long double t = static_cast<long double>(u(k)) + a * static_cast<long double>(d(k));
    tail += t * t;
  }
  return head > 0 && head * head > tail;
}

// The boundary along the ray u + a d (u inside) by bisection on membership: the last a inside
// to 2^-80 of the bracket, or infinity when u + 1e12 d is still inside.
template <int D>
double bisect_step(const Ref<D>& u, const Ref<D>& d) {
  long double lo = 0, hi = 1;
  while (inside_long(u, d, hi)) {
    hi *= 2;
    if (hi > 1e12L) return std::numeric_limits<double>::infinity();
  }
  for (int k = 0; k < 120 && hi - lo > 0; ++k) {
    const long double mid = (lo + hi) / 2;
    (inside_long(u, d, mid) ? lo : hi) = mid;
  }
  return static_cast<double>(lo);
}

// Lanes of D packs, component by component, from and to cone vectors in double.
template <class P, int D>
struct Block {
  using S = typename P::Scalar;
  alignas(64) S v[D][P::width];
  detail::ConeVec<P, D> load() const {
    detail::ConeVec<P, D> out;
    for (int r = 0; r < D; ++r) out[static_cast<std::size_t>(r)] = P::load(v[r]);
    return out;
  }
  void set(int lane, const Ref<D>& x) {
    for (int r = 0; r < D; ++r) v[r][lane] = S(x(r));
  }
  // Lane `lane` of x, as stored (the data the pack sees, in double).
  Ref<D> get(int lane) const {
    Ref<D> x;
    for (int r = 0; r < D; ++r) x(r) = double(v[r][lane]);
    return x;
  }
  static Ref<D> lane(const detail::ConeVec<P, D>& x, int lane) {
    alignas(64) S tmp[P::width];
    Ref<D> out;
    for (int r = 0; r < D; ++r) {
      x[static_cast<std::size_t>(r)].store(tmp);
      out(r) = double(tmp[lane]);
    }
    return out;
  }
};

template <class P>
double lane_of(P p, int lane) {
  alignas(64) typename P::Scalar tmp[P::width];
  p.store(tmp);
  return double(tmp[lane]);
}

template <class P, int D>
void check_cones(std::mt19937& rng, int count) {
  using S = typename P::Scalar;
  using B = Block<P, D>;
  constexpr int w = P::width;
  grip_test::Uniform unit(-1.0, 1.0);
  const Ref<D> e = Ref<D>::Unit(0);
  for (int o = 0; o < count; o += w) {
    B u, z, x, d, du;
    for (int j = 0; j < w; ++j) {
      const bool used = o + j < count;
      u.set(j, used ? interior<D>(rng) : e);
      z.set(j, used ? interior<D>(rng) : e);
      Ref<D> r;
      for (int k = 0; k < D; ++k) r(k) = unit(rng);
      x.set(j, used ? r : Ref<D>(Ref<D>::Zero()));
      d.set(j, used ? Ref<D>(interior<D>(rng) - 2.0 * interior<D>(rng)) : Ref<D>::Zero());
      du.set(j, used ? interior<D>(rng) : e);  // a divisor, interior
    }
    const auto pu = u.load(), pz = z.load(), px = x.load(), pd = d.load(), pl = du.load();
    const detail::NtFrame<P, D> k = detail::nt_frame<P, D>(pu, pz);
    const auto w_z = detail::nt_frame_apply<false, P, D>(k, pz);
    const auto wi_u = detail::nt_frame_apply<true, P, D>(k, pu);
    const auto round_trip = detail::nt_frame_apply<false, P, D>(k, detail::nt_frame_apply<true, P, D>(k, px));
    const auto prod = detail::jordan_product<P, D>(pu, pz);
    const auto quot = detail::jordan_divide<P, D>(pl, detail::cone_det<P, D>(pl), px);
    const P step = detail::cone_ray_step<P, D>(pu, detail::cone_det<P, D>(pu), pd);
    const unsigned ok = k.ok.bits();
    for (int j = 0; j < w; ++j) {
      const int cone = o + j;
      CAPTURE(cone);
      const Ref<D> uj = u.get(j), zj = z.get(j), xj = x.get(j), dj = d.get(j), lj = du.get(j);
      const Ref<D> lambda = B::lane(k.lambda, j);
      CHECK(((ok >> j) & 1u) == 1u);
      if (o + j >= count) {
        // A padded lane: u = z = e, so W = I (beta = 1, d+ = d- = 1) and lambda = e; a zero
        // direction never limits the step.
        CHECK((lambda - e).norm() <= grip_test::roundoff<S>(8, 1, 1));
        CHECK(std::isinf(lane_of(step, j)));
        continue;
      }
      // W z = W^-1 u = lambda, u . z = |lambda|^2, lambda inside Q. The scaling's entries grow
      // with its condition, |u|^2 / det u and |z|^2 / det z (the head lifted 0.01 to 2 above
      // the tail: up to about 1e4); the frame keeps each eigen-direction to its own relative
      // accuracy, so a few tens of roundings of |u| + |z| bound the identities' errors: k = 64.
      const double scale = uj.norm() + zj.norm();
      CHECK((B::lane(w_z, j) - lambda).norm() <= grip_test::roundoff<S>(64, 1, scale));
      CHECK((B::lane(wi_u, j) - lambda).norm() <= grip_test::roundoff<S>(64, 1, scale));
      CHECK(std::abs(lambda.squaredNorm() - uj.dot(zj)) <= grip_test::roundoff<S>(64, 1, scale * scale));
      CHECK(grip_test::soc_interior(lambda));
      // ... the same lambda as the scalar reference's W = beta (2 v v^T - J), in double.
      grip_test::SocScaling<double, D> ref;
      REQUIRE(ref.set(uj, zj));
      CHECK((lambda - ref.apply(zj)).norm() <= grip_test::roundoff<S>(64, 1, scale));
      CHECK((lambda - ref.apply_inverse(uj)).norm() <= grip_test::roundoff<S>(64, 1, scale));
      // The determinants (the product form keeps them to a few roundings of u_0^2).
      CHECK(std::abs(lane_of(k.det_u, j) - grip_test::soc_det(uj)) <= grip_test::roundoff<S>(8, 1, uj(0) * uj(0)));
      CHECK(std::abs(lane_of(k.det_lambda, j) - std::sqrt(grip_test::soc_det(uj) * grip_test::soc_det(zj))) <=
            grip_test::roundoff<S>(16, 1, uj(0) * zj(0)));
      // W W^-1 x = x: the two applications' errors, each a few roundings of |x| times the
      // scaling's spread d+ / d- (x's components along e+ and e- meet both eigenvalues).
      const double spread = lane_of(k.dp, j) / lane_of(k.dm, j);
      CHECK((B::lane(round_trip, j) - xj).norm() <= grip_test::roundoff<S>(64, 1, xj.norm() * (1 + spread)));
      // The Jordan product's definition (u . z, u_0 z_1 + z_0 u_1), each entry a dot product
      // of D terms or a fused product: k = 2 D of |u| |z|.
      CHECK((B::lane(prod, j) - grip_test::soc_product(uj, zj)).norm() <=
            grip_test::roundoff<S>(2 * D, 1, uj.norm() * zj.norm()));
      // Division as the product's inverse: l o (l \ x) = x. The quotient's head is
      // (l_0 x_0 - l_1 . x_1) / det l, its numerator within a few roundings of |l| |x|; the tail
      // (x_1 - q_0 l_1) / l_0 adds |l| / l_0 times the head's error: the quotient's rounding
      // scale is qe = |x| |l| / det l (1 + |l| / l_0), and l o q's is |l| qe (k = 64 of each).
      const Ref<D> q = B::lane(quot, j);
      const double qe = xj.norm() * lj.norm() / grip_test::soc_det(lj) * (1 + lj.norm() / lj(0));
      CHECK((grip_test::soc_product(lj, q) - xj).norm() <= grip_test::roundoff<S>(64, 1, lj.norm() * qe));
      CHECK((q - grip_test::soc_divide(lj, xj)).norm() <= grip_test::roundoff<S>(64, 1, qe));
      // The step to the boundary against bisection on membership (in long double on the data
      // the pack sees). The step is the least root of f(a) = det(u + a d) = A a^2 + 2 B a + C
      // (of u_0 + a d_0 for D = 1), whose coefficients carry a few roundings each: f is off by
      // k u (|u| + a |d|)^2 near the root (k u (|u| + a |d|) for D = 1), which moves the root by
      // that over |f'(a)|, plus the root's own rounding (k = 16). Where the ray grazes the cone
      // f' vanishes (a double root) and so does the bound's meaning: check_axis covers that.
      const double a = lane_of(step, j), a_ref = bisect_step<D>(uj, dj);
      if (std::isinf(a_ref)) {
        CHECK(std::isinf(a));
      } else {
        CHECK(a > 0);
        const double reach = uj.norm() + a_ref * dj.norm();
        double slope = std::abs(dj(0)), size = reach;
        if constexpr (D > 1) {
          const double qa = grip_test::soc_det(dj),
                       qb = uj(0) * dj(0) - uj.template tail<D - 1>().dot(dj.template tail<D - 1>());
          slope = 2 * std::abs(qa * a_ref + qb);
          size = reach * reach;
        }
        CHECK(std::abs(a - a_ref) <= grip_test::roundoff<S>(16, 1, size / slope + a_ref));
      }
    }
  }
}

// A lane outside the cone (or on its boundary) has no scaling: ok false there only.
template <class P>
void check_invalid() {
  using B = Block<P, 3>;
  B u, z;
  for (int j = 0; j < P::width; ++j) {
    u.set(j, Ref<3>(2.0, 0.5, 0.5));
    z.set(j, Ref<3>(1.0, 0.1, -0.2));
  }
  u.set(0, Ref<3>(0.5, 1.0, 0.0));                               // outside
  if (P::width > 1) z.set(P::width - 1, Ref<3>(1.0, 1.0, 0.0));  // on the boundary
  const auto k = detail::nt_frame<P, 3>(u.load(), z.load());
  const unsigned ok = k.ok.bits();
  CHECK((ok & 1u) == 0u);
  for (int j = 1; j < P::width; ++j) CHECK(((ok >> j) & 1u) == (j == P::width - 1 ? 0u : 1u));
}

template <class P>
void check_pack_all() {
  std::mt19937 rng(41);
  for (int count = 1; count <= 2 * P::width + 1; ++count)
    for (int rep = 0; rep < 8; ++rep) {
      check_cones<P, 1>(rng, count);
      check_cones<P, 2>(rng, count);
      check_cones<P, 3>(rng, count);
      check_cones<P, 4>(rng, count);
    }
  check_invalid<P>();
}

// The double root of the step along the axis: u = 2s e, d = -s e, det(u + a d) = s^2 (2 - a)^2,
// whose discriminant is 0 in exact arithmetic and may round either way; the bound -u_0 / d_0
// decides it.
template <class P, int D>
void check_axis() {
  using S = typename P::Scalar;
  using B = Block<P, D>;
  for (const double s : {1.0, 1e-7, 3.3, 1e5}) {
    B u, d;
    for (int j = 0; j < P::width; ++j) {
      u.set(j, Ref<D>(Ref<D>::Unit(0) * 2 * s));
      d.set(j, Ref<D>(Ref<D>::Unit(0) * -s));
    }
    const auto pu = u.load();
    const P a = detail::cone_ray_step<P, D>(pu, detail::cone_det<P, D>(pu), d.load());
    // With B^2 - A C contracted into a fused multiply-add, the discriminant is the rounding
    // error of A C, whose square root moves the quadratic's root by up to sqrt(u) relative:
    // the bound is the square root of the rounding bound.
    const double tol = std::sqrt(grip_test::roundoff<S>(8, 1, 1.0));
    for (int j = 0; j < P::width; ++j) CHECK(lane_of(a, j) == doctest::Approx(2.0).epsilon(tol));
  }
}

}  // namespace

TEST_CASE("second-order cone algebra on packs: the compiled pack against the scalar definitions") {
  check_pack_all<detail::SimdPack<double>>();
  check_axis<detail::SimdPack<double>, 3>();
  check_axis<detail::SimdPack<double>, 4>();
}

#if GRIP_SIMD_AVX2
TEST_CASE("second-order cone algebra on packs: the 4-lane AVX2 pack") {
  check_pack_all<detail::PackD4>();
  check_axis<detail::PackD4, 3>();
}
#endif

TEST_CASE_TEMPLATE("second-order cone algebra on packs: the scalar pack", S, double, float) {
  check_pack_all<detail::ScalarPack<S>>();
  check_axis<detail::ScalarPack<S>, 3>();
  check_axis<detail::ScalarPack<S>, 4>();
}
