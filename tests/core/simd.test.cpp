// The SIMD packs of core/simd.hpp (what solve/detail/coulomb_pass.hpp computes with), lane by lane
// against plain scalar arithmetic (and mul_add, neg_mul_add against std::fma): the pack this translation unit compiles
// (CMake builds this file again with -march=native and with AVX2), and the scalar pack for float. Arithmetic and the
// square root must match bit for bit (IEEE operations, correctly rounded), comparisons must be false for NaN (ordered),
// select must pick per lane, and the lane sums must equal the scalar sums up to the order of the additions.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <grip/core/simd.hpp>
#include "support/random.hpp"

using namespace grip;

namespace {

template <class S>
bool same_bits(S a, S b) {
  return std::memcmp(&a, &b, sizeof(S)) == 0;
}

template <class P, class S>
void check_pack() {
  constexpr int w = P::width;
  std::mt19937 rng(81);
  grip_test::Normal n01(0.0, 1.0);
  const S specials[] = {S(0),
                        -S(0),
                        S(1),
                        -S(1),
                        std::numeric_limits<S>::infinity(),
                        -std::numeric_limits<S>::infinity(),
                        std::numeric_limits<S>::quiet_NaN(),
                        std::numeric_limits<S>::denorm_min(),
                        std::numeric_limits<S>::max(),
                        S(1e-30f)};
  for (int rep = 0; rep < 400; ++rep) {
    S a[w], b[w], out[w];
    for (int j = 0; j < w; ++j) {
      const double ea = std::exp(4.0 * n01(rng)), ma = n01(rng), eb = std::exp(4.0 * n01(rng)), mb = n01(rng);
      a[j] = rep % 4 == 3 ? specials[(rep + 3 * j) % 10] : S(ea * ma);
      b[j] = rep % 5 == 4 ? specials[(rep + j) % 10] : S(eb * mb);
    }
    const P pa = P::load(a), pb = P::load(b);
    const auto lanes = [&](P p) {
      p.store(out);
      return out;
    };
    CAPTURE(rep);
    for (int j = 0; j < w; ++j) CHECK(same_bits(lanes(pa + pb)[j], S(a[j] + b[j])));
    for (int j = 0; j < w; ++j) CHECK(same_bits(lanes(pa - pb)[j], S(a[j] - b[j])));
    for (int j = 0; j < w; ++j) CHECK(same_bits(lanes(pa * pb)[j], S(a[j] * b[j])));
    for (int j = 0; j < w; ++j) {
      const S q = a[j] / b[j];
      CHECK((same_bits(lanes(pa / pb)[j], q) || (std::isnan(q) && std::isnan(lanes(pa / pb)[j]))));
    }
    for (int j = 0; j < w; ++j) {
      const S r = std::sqrt(std::abs(a[j]));
      const S got = lanes(sqrt(abs(pa)))[j];
      CHECK((same_bits(got, r) || (std::isnan(r) && std::isnan(got))));
    }
    // mul_add and neg_mul_add: one rounding (std::fma) in the SIMD packs; the scalar pack may
    // round once or twice.
    const P pc = P::load(b);  // c = b: a * b + b and b - a * b
    for (int j = 0; j < w; ++j) {
      const S fused = std::fma(a[j], b[j], b[j]), neg = std::fma(-a[j], b[j], b[j]);
      const S got = lanes(mul_add(pa, pb, pc))[j], got_neg = lanes(neg_mul_add(pa, pb, pc))[j];
      const bool nan = std::isnan(fused) && std::isnan(got), nan_neg = std::isnan(neg) && std::isnan(got_neg);
      if (w > 1) {
        CHECK((same_bits(got, fused) || nan));
        CHECK((same_bits(got_neg, neg) || nan_neg));
      } else {
        CHECK((same_bits(got, fused) || same_bits(got, S(a[j] * b[j] + b[j])) || nan));
        CHECK((same_bits(got_neg, neg) || same_bits(got_neg, S(b[j] - a[j] * b[j])) || nan_neg));
      }
    }
    // Comparisons and select: lanes of a where the condition holds, else of b.
    const auto pick = [&](typename P::Mask m) {
      select(m, pa, pb).store(out);
      return out;
    };
    for (int j = 0; j < w; ++j) {
      const S lt = a[j] < b[j] ? a[j] : b[j], le = a[j] <= b[j] ? a[j] : b[j], gt = a[j] > b[j] ? a[j] : b[j];
      CHECK(same_bits(pick(pa < pb)[j], lt));
      CHECK(same_bits(pick(pa <= pb)[j], le));
      CHECK(same_bits(pick(pa > pb)[j], gt));
      const bool both = (a[j] < b[j]) && (a[j] > S(0));
      const bool either = (a[j] < b[j]) || (a[j] > S(0));
      const bool neither = !(a[j] < b[j]);
      const P zero = P::set1(S(0));
      CHECK(same_bits(pick((pa < pb) & (pa > zero))[j], both ? a[j] : b[j]));
      CHECK(same_bits(pick((pa < pb) | (pa > zero))[j], either ? a[j] : b[j]));
      CHECK(same_bits(pick(!(pa < pb))[j], neither ? a[j] : b[j]));
    }
  }
  // Lane sums: sum_each over 40 packs against sum() and a scalar sum of the lanes.
  std::vector<P> acc(40, P::set1(S(0)));
  std::vector<S> lanes_of(40 * w);
  for (int e = 0; e < 40; ++e) {
    for (int j = 0; j < w; ++j) {
      const double m = n01(rng), e2 = std::exp(2.0 * n01(rng));
      lanes_of[std::size_t(e * w + j)] = S(m * e2);
    }
    acc[std::size_t(e)] = P::load(&lanes_of[std::size_t(e * w)]);
  }
  S total[40];
  P::sum_each(acc.data(), 40, total);
  for (int e = 0; e < 40; ++e) {
    double ref = 0.0, mag = 0.0;
    for (int j = 0; j < w; ++j) {
      ref += double(lanes_of[std::size_t(e * w + j)]);
      mag += std::abs(double(lanes_of[std::size_t(e * w + j)]));
    }
    const double eps = double(std::numeric_limits<S>::epsilon());
    CAPTURE(e);
    CHECK(std::abs(double(total[e]) - ref) <= 8 * eps * mag);
    CHECK(std::abs(double(acc[std::size_t(e)].sum()) - ref) <= 8 * eps * mag);
  }
}

}  // namespace

TEST_CASE("simd packs: lane by lane as scalar arithmetic") {
  MESSAGE("SimdPack<double> has " << detail::SimdPack<double>::width << " lanes");
  check_pack<detail::SimdPack<double>, double>();
  check_pack<detail::SimdPack<float>, float>();
  check_pack<detail::ScalarPack<double>, double>();
}
