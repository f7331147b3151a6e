// core/simd_blocks.hpp: a pass over blocks of lanes that writes its per-lane sums when they fit
// one block. for_each_block must visit every block once, in order: in the first form alone when
// Single, in the second form otherwise (the block at 0 in the first with Peel), and in the second
// form everywhere where the build optimises for size; the sums of lane_add,
// lane_add_mul and lane_sub_mul must equal those of sums cleared to zero and added to in plain scalar arithmetic, lane
// by lane (to one rounding of each product: the scalar pack's mul_add rounds twice, a compiler may fuse a - b c), for
// the packs this translation unit compiles (CMake builds this file again with -march=native and with AVX2) and the
// scalar pack.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include <grip/core/simd_blocks.hpp>
#include "support/random.hpp"

using namespace grip;

namespace {

#if defined(__OPTIMIZE_SIZE__)
constexpr bool size_build = true;
#else
constexpr bool size_build = false;
#endif

// The offsets for_each_block visits and whether each is in the first form.
template <bool Single, int Width, bool Peel = false>
void visits(int blocks, std::vector<int>& offsets, std::vector<bool>& first) {
  offsets.clear();
  first.clear();
  detail::for_each_block<Single, Width, Peel>(blocks, [&](int o, auto f) {
    offsets.push_back(o);
    first.push_back(decltype(f)::value);
  });
}

// Sums of `blocks` blocks of random lanes through the three helpers, against scalar sums.
template <class P, class S>
bool sums_match(int blocks, std::mt19937& rng) {
  constexpr int w = P::width;
  grip_test::Normal n01(0.0, 1.0);
  const int lanes = blocks * w;
  std::vector<S> a(static_cast<std::size_t>(lanes)), b(a.size()), c(a.size());
  for (int i = 0; i < lanes; ++i) {
    a[static_cast<std::size_t>(i)] = S(n01(rng));
    b[static_cast<std::size_t>(i)] = S(n01(rng));
    c[static_cast<std::size_t>(i)] = S(n01(rng));
  }
  P sums[3];
  for (P& s : sums) s = P::set1(S(0));
  detail::for_each_block<false, w, true>(blocks, [&](int o, auto f) {
    constexpr bool First = decltype(f)::value;
    const P pa = P::load(a.data() + o), pb = P::load(b.data() + o), pc = P::load(c.data() + o);
    detail::lane_add<First>(sums[0], pc);
    detail::lane_add_mul<First>(sums[1], pa, pb);
    detail::lane_sub_mul<First>(sums[2], pa, pc);
  });
  S got[3][w];
  for (int k = 0; k < 3; ++k) sums[k].store(got[k]);
  bool ok = true;
  for (int j = 0; j < w; ++j) {
    S want[3] = {S(0), S(0), S(0)};
    for (int blk = 0; blk < blocks; ++blk) {
      const auto i = static_cast<std::size_t>(blk * w + j);
      want[0] = want[0] + c[i];
      want[1] = std::fma(a[i], b[i], want[1]);
      want[2] = want[2] - a[i] * c[i];
    }
    // A product is rounded before its addition or fused into it: within one rounding of each.
    S slack(0);
    for (int blk = 0; blk < blocks; ++blk) {
      const auto i = static_cast<std::size_t>(blk * w + j);
      slack += (std::abs(a[i] * b[i]) + std::abs(a[i] * c[i])) * std::numeric_limits<S>::epsilon();
    }
    ok = ok && got[0][j] == want[0] && std::abs(got[1][j] - want[1]) <= slack && std::abs(got[2][j] - want[2]) <= slack;
  }
  return ok;
}

template <class P, class S>
void check_sums() {
  std::mt19937 rng(57);
  for (int blocks = 1; blocks <= 5; ++blocks)
    for (int rep = 0; rep < 20; ++rep) CHECK(sums_match<P, S>(blocks, rng));
}

}  // namespace

TEST_CASE("simd blocks: every block once, in order, in the form Single and Peel ask for") {
  std::vector<int> offsets;
  std::vector<bool> first;
  for (int blocks = 0; blocks <= 4; ++blocks) {
    visits<false, 8>(blocks, offsets, first);
    REQUIRE(offsets.size() == static_cast<std::size_t>(blocks));
    for (int b = 0; b < blocks; ++b) {
      CHECK(offsets[static_cast<std::size_t>(b)] == 8 * b);
      CHECK(!first[static_cast<std::size_t>(b)]);
    }
    visits<false, 4, true>(blocks, offsets, first);
    REQUIRE(offsets.size() == static_cast<std::size_t>(blocks));
    for (int b = 0; b < blocks; ++b) {
      CHECK(offsets[static_cast<std::size_t>(b)] == 4 * b);
      CHECK(first[static_cast<std::size_t>(b)] == (b == 0 && !size_build));
    }
  }
  // Single: at most one block; the first form alone where the build optimises for speed.
  visits<true, 4>(1, offsets, first);
  REQUIRE(offsets.size() == 1u);
  CHECK(offsets[0] == 0);
  CHECK(first[0] == !size_build);
  visits<true, 4>(0, offsets, first);
  CHECK(offsets.empty());
}

TEST_CASE("simd blocks: the sums equal sums cleared and added to, lane by lane") {
  check_sums<detail::SimdPack<double>, double>();
  check_sums<detail::SimdPack<float>, float>();
  check_sums<detail::ScalarPack<double>, double>();
}
