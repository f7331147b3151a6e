#pragma once
/// \file
/// Rows of an array of structures loaded into the packs of core/simd.hpp, transposed: row j is
/// the four scalars at p + j * stride, and lane j of the packs c0, c1, c2, c3 receives its
/// values 0, 1, 2 and 3. What a vectorised pass over records stored one after another (the
/// contacts of a Grasp, each with its normal and friction side by side) uses to read them in
/// place, where a structure of arrays would be a second copy to keep in step.
///
/// - load_rows4(p, stride, c0, c1, c2, c3): the pack's `width` rows.
/// - load_rows4(p, stride, k, c0, c1, c2, c3): only rows j < k (k >= 1) read, lanes k and up
///   zero; for the last, partial block of a pass (ScalarPack, PackD8, and PackD4 with AVX-512).
/// Nothing outside the rows read is touched, so p may point into the last record of an array.

#include <cstddef>

#include "grip/core/simd.hpp"

namespace grip {
namespace detail {

/// ScalarPack: row 0 itself (k >= 1 is the whole pack).
template <class S>
GRIP_ALWAYS_INLINE void load_rows4(const S* p, std::ptrdiff_t /*stride*/, ScalarPack<S>& c0, ScalarPack<S>& c1,
                                   ScalarPack<S>& c2, ScalarPack<S>& c3) {
  c0 = {p[0]};
  c1 = {p[1]};
  c2 = {p[2]};
  c3 = {p[3]};
}
template <class S>
GRIP_ALWAYS_INLINE void load_rows4(const S* p, std::ptrdiff_t stride, int /*k*/, ScalarPack<S>& c0, ScalarPack<S>& c1,
                                   ScalarPack<S>& c2, ScalarPack<S>& c3) {
  load_rows4(p, stride, c0, c1, c2, c3);
}

#if GRIP_SIMD_AVX512 || GRIP_SIMD_AVX2
/// The 4 x 4 transpose of rows r0 .. r3 into columns c0 .. c3: two unpacks pair the rows' even
/// and odd values, one 128-bit permute per column joins the pairs.
GRIP_ALWAYS_INLINE void transpose4(__m256d r0, __m256d r1, __m256d r2, __m256d r3, __m256d& c0, __m256d& c1,
                                   __m256d& c2, __m256d& c3) {
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
  c0 = _mm256_permute2f128_pd(t0, t2, 0x20);
  c1 = _mm256_permute2f128_pd(t1, t3, 0x20);
  c2 = _mm256_permute2f128_pd(t0, t2, 0x31);
  c3 = _mm256_permute2f128_pd(t1, t3, 0x31);
}
#endif

#if GRIP_SIMD_AVX2
/// PackD4: four rows.
GRIP_ALWAYS_INLINE void load_rows4(const double* p, std::ptrdiff_t stride, PackD4& c0, PackD4& c1, PackD4& c2,
                                   PackD4& c3) {
  transpose4(_mm256_loadu_pd(p), _mm256_loadu_pd(p + stride), _mm256_loadu_pd(p + 2 * stride),
             _mm256_loadu_pd(p + 3 * stride), c0.v, c1.v, c2.v, c3.v);
}
#endif

#if GRIP_SIMD_AVX512
/// Row j of p when j < k, else zero (a masked load: nothing read).
GRIP_ALWAYS_INLINE __m256d row_or_zero(const double* p, std::ptrdiff_t stride, int j, int k) {
  return _mm256_maskz_loadu_pd(static_cast<__mmask8>(j < k ? 0x0F : 0x00), p + j * stride);
}

/// PackD4, the first k rows (AVX-512VL masked loads).
GRIP_ALWAYS_INLINE void load_rows4(const double* p, std::ptrdiff_t stride, int k, PackD4& c0, PackD4& c1, PackD4& c2,
                                   PackD4& c3) {
  transpose4(row_or_zero(p, stride, 0, k), row_or_zero(p, stride, 1, k), row_or_zero(p, stride, 2, k),
             row_or_zero(p, stride, 3, k), c0.v, c1.v, c2.v, c3.v);
}

/// PackD8, the first k rows. Registers hold rows (0 | 2), (1 | 3), (4 | 6) and (5 | 7) in their
/// 256-bit halves; two unpacks per pair of registers give 128-bit blocks of two rows' values
/// (rows 0 1 | 0 1 | 2 3 | 2 3 ...), and one block shuffle per column puts its eight lanes in
/// row order: 8 loads, 4 inserts, 4 unpacks and 4 shuffles.
GRIP_ALWAYS_INLINE void load_rows4(const double* p, std::ptrdiff_t stride, int k, PackD8& c0, PackD8& c1, PackD8& c2,
                                   PackD8& c3) {
  // Masked forms with a zero source and every lane kept: GCC 12 reports the undefined source of
  // the unmasked intrinsics as used uninitialized.
  constexpr __mmask8 all = 0xFF;
  const auto rows = [&](int lo, int hi) {
    const __m512d low = _mm512_maskz_loadu_pd(static_cast<__mmask8>(lo < k ? 0x0F : 0x00), p + lo * stride);
    return _mm512_maskz_insertf64x4(all, low, row_or_zero(p, stride, hi, k), 1);
  };
  const __m512d r02 = rows(0, 2), r13 = rows(1, 3), r46 = rows(4, 6), r57 = rows(5, 7);
  const __m512d z = _mm512_setzero_pd();
  const __m512d e0 = _mm512_mask_unpacklo_pd(z, all, r02, r13), o0 = _mm512_mask_unpackhi_pd(z, all, r02, r13);
  const __m512d e1 = _mm512_mask_unpacklo_pd(z, all, r46, r57), o1 = _mm512_mask_unpackhi_pd(z, all, r46, r57);
  // Blocks 0 and 2 of each hold values 0 (e) or 1 (o); blocks 1 and 3 values 2 or 3.
  c0.v = _mm512_mask_shuffle_f64x2(z, all, e0, e1, 0x88);
  c1.v = _mm512_mask_shuffle_f64x2(z, all, o0, o1, 0x88);
  c2.v = _mm512_mask_shuffle_f64x2(z, all, e0, e1, 0xDD);
  c3.v = _mm512_mask_shuffle_f64x2(z, all, o0, o1, 0xDD);
}
GRIP_ALWAYS_INLINE void load_rows4(const double* p, std::ptrdiff_t stride, PackD8& c0, PackD8& c1, PackD8& c2,
                                   PackD8& c3) {
  load_rows4(p, stride, 8, c0, c1, c2, c3);
}
#endif

}  // namespace detail
}  // namespace grip
