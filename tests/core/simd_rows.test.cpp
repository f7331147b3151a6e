// core/simd_rows.hpp: rows of records loaded into packs transposed. Every pack this translation
// unit compiles (CMake builds this file again with -march=native and with AVX2) against the rows
// read one value at a time: lane j of pack c is value c of row j, bit for bit, for every stride
// and every count of rows k (lanes k and up zero). The rows are put right before a page that
// may not be read, so a load of anything past row k - 1 ends the test with a fault.
#include <doctest/doctest.h>

#include <cstddef>
#include <cstring>
#include <random>
#include <vector>

#include <grip/core/simd_rows.hpp>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

using namespace grip;

namespace {

template <class P, class S>
void lanes_of(const P& p, S* out) {
  p.store(out);
}

// Checks load_rows4 of k rows at `rows` (stride `stride`), masked form when Masked.
template <class P, bool Masked, class S>
bool rows_transposed(const S* rows, std::ptrdiff_t stride, int k) {
  constexpr int w = P::width;
  P c[4];
  if constexpr (Masked)
    detail::load_rows4(rows, stride, k, c[0], c[1], c[2], c[3]);
  else
    detail::load_rows4(rows, stride, c[0], c[1], c[2], c[3]);
  bool ok = true;
  for (int v = 0; v < 4; ++v) {
    S out[w];
    lanes_of(c[v], out);
    for (int j = 0; j < w; ++j) {
      const S want = j < k ? rows[j * stride + v] : S(0);
      ok = ok && std::memcmp(&out[j], &want, sizeof(S)) == 0;
    }
  }
  return ok;
}

// Rows of random values with strides 4 (packed) to 13, and the record layouts in between.
template <class P, bool Masked, class S>
void check_rows() {
  constexpr int w = P::width;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  for (int stride = 4; stride <= 13; ++stride) {
    std::vector<S> data(static_cast<std::size_t>(stride * w + 4));
    for (S& x : data) x = S(u(rng));
    for (int k = Masked ? 1 : w; k <= w; ++k) {
      CAPTURE(stride);
      CAPTURE(k);
      CHECK(rows_transposed<P, Masked>(data.data() + 1, stride, k));
    }
  }
}

#if defined(__linux__)
// k rows whose last value is the last before a page that may not be read.
template <class P, bool Masked, class S>
bool rows_before_guard_page(int k, std::ptrdiff_t stride) {
  const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  void* mem = mmap(nullptr, 2 * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  REQUIRE(mem != MAP_FAILED);
  REQUIRE(mprotect(static_cast<char*>(mem) + page, page, PROT_NONE) == 0);
  S* end = reinterpret_cast<S*>(static_cast<char*>(mem) + page);
  S* rows = end - ((k - 1) * stride + 4);
  for (S* p = rows; p < end; ++p) *p = S(p - rows);
  const bool ok = rows_transposed<P, Masked>(rows, stride, k);
  munmap(mem, 2 * page);
  return ok;
}
#endif

}  // namespace

TEST_CASE("load_rows4 transposes rows into lanes, the masked form only the first k rows") {
  check_rows<detail::ScalarPack<double>, false, double>();
  check_rows<detail::ScalarPack<double>, true, double>();
  check_rows<detail::ScalarPack<float>, true, float>();
#if GRIP_SIMD_AVX2
  check_rows<detail::PackD4, false, double>();
#endif
#if GRIP_SIMD_AVX512
  check_rows<detail::PackD4, true, double>();
  check_rows<detail::PackD8, false, double>();
  check_rows<detail::PackD8, true, double>();
#endif
  MESSAGE("widest pack for double: " << detail::SimdPack<double>::width << " lanes");
}

#if defined(__linux__)
TEST_CASE("load_rows4 reads nothing past its k rows (the next page may not be read)") {
  for (int stride : {4, 11}) {
    CAPTURE(stride);
    CHECK(rows_before_guard_page<detail::ScalarPack<double>, true, double>(1, stride));
#if GRIP_SIMD_AVX2
    CHECK(rows_before_guard_page<detail::PackD4, false, double>(4, stride));
#endif
#if GRIP_SIMD_AVX512
    for (int k = 1; k <= 4; ++k) CHECK(rows_before_guard_page<detail::PackD4, true, double>(k, stride));
    for (int k = 1; k <= 8; ++k) CHECK(rows_before_guard_page<detail::PackD8, true, double>(k, stride));
#endif
  }
}
#endif
