#pragma once
/// \file
/// Which SIMD instructions grip's vectorised passes use in this translation unit, chosen by the
/// compiler flags (nothing is detected at run time): GRIP_SIMD_AVX512 (AVX-512F and VL, e.g.
/// -march=native on a recent x86-64, or -march=x86-64-v4), GRIP_SIMD_AVX2 (AVX2 and FMA,
/// -march=x86-64-v3), each 1 or 0; defining GRIP_NO_SIMD turns both off. As with Eigen, compile every translation unit
/// of one program with the same SIMD flags.

#include <cmath>

/// Marks a function the compiler must inline (the SIMD passes into their callers, where their
/// small results stay in registers).
#if defined(__GNUC__) || defined(__clang__)
#define GRIP_ALWAYS_INLINE inline __attribute__((always_inline))
#elif defined(_MSC_VER)
#define GRIP_ALWAYS_INLINE __forceinline
#else
#define GRIP_ALWAYS_INLINE inline
#endif

/// 1 when the vectorised passes use AVX-512 (the compiler targets AVX-512F and AVX-512VL and
/// GRIP_NO_SIMD is not defined), else 0.
#if defined(__AVX512F__) && defined(__AVX512VL__) && !defined(GRIP_NO_SIMD)
#define GRIP_SIMD_AVX512 1
#else
#define GRIP_SIMD_AVX512 0
#endif
/// 1 when the vectorised passes may use AVX2 (the compiler targets AVX2 and FMA and GRIP_NO_SIMD
/// is not defined), else 0. Set independently of GRIP_SIMD_AVX512: an AVX-512 build usually has both.
#if defined(__AVX2__) && defined(__FMA__) && !defined(GRIP_NO_SIMD)
#define GRIP_SIMD_AVX2 1
#else
#define GRIP_SIMD_AVX2 0
#endif
#if GRIP_SIMD_AVX512 || GRIP_SIMD_AVX2
#include <immintrin.h>
#endif

namespace grip {
namespace detail {

/// A register of scalars for grip's vectorised passes: `width` lanes, loaded and stored from
/// arrays (unaligned), with lane-wise arithmetic, mul_add and neg_mul_add, comparisons giving a Mask, select,
/// abs, the correctly rounded square root (as std::sqrt) and the sum of the lanes. The generic type is
/// one scalar (the portable fallback, and float everywhere); SimdPack<double> is 8 lanes with
/// AVX-512, 4 with AVX2.
template <class S>
struct ScalarPack {
  static constexpr int width = 1;
  /// A lane-wise truth value: combine with &, |, !.
  struct Mask {
    bool m;
    friend Mask operator&(Mask a, Mask b) { return {a.m && b.m}; }
    friend Mask operator|(Mask a, Mask b) { return {a.m || b.m}; }
    friend Mask operator!(Mask a) { return {!a.m}; }
  };
  S v;
  static ScalarPack load(const S* p) { return {*p}; }
  static ScalarPack set1(S s) { return {s}; }
  void store(S* p) const { *p = v; }
  S sum() const { return v; }
  /// out[e] = a[e].sum() for 0 <= e < count.
  static void sum_each(const ScalarPack* a, int count, S* out) {
    for (int e = 0; e < count; ++e) out[e] = a[e].v;
  }
  friend ScalarPack operator+(ScalarPack a, ScalarPack b) { return {a.v + b.v}; }
  friend ScalarPack operator-(ScalarPack a, ScalarPack b) { return {a.v - b.v}; }
  friend ScalarPack operator*(ScalarPack a, ScalarPack b) { return {a.v * b.v}; }
  friend ScalarPack operator/(ScalarPack a, ScalarPack b) { return {a.v / b.v}; }
  friend Mask operator<(ScalarPack a, ScalarPack b) { return {a.v < b.v}; }
  friend Mask operator<=(ScalarPack a, ScalarPack b) { return {a.v <= b.v}; }
  friend Mask operator>(ScalarPack a, ScalarPack b) { return {a.v > b.v}; }
  friend ScalarPack select(Mask m, ScalarPack a, ScalarPack b) { return m.m ? a : b; }
  friend ScalarPack abs(ScalarPack a) { return {std::abs(a.v)}; }
  friend ScalarPack sqrt(ScalarPack a) { return {std::sqrt(a.v)}; }
  /// a * b + c (one rounding where the pack has FMA: AVX-512, AVX2; two here).
  friend ScalarPack mul_add(ScalarPack a, ScalarPack b, ScalarPack c) { return {a.v * b.v + c.v}; }
  /// c - a * b (one rounding where the pack has FMA, as mul_add).
  friend ScalarPack neg_mul_add(ScalarPack a, ScalarPack b, ScalarPack c) { return {c.v - a.v * b.v}; }
};

#if GRIP_SIMD_AVX512 || GRIP_SIMD_AVX2
/// The sum of the four lanes of an AVX register (both packs' sum()).
inline double sum_lanes(__m256d q) {
  const __m128d h = _mm_add_pd(_mm256_castpd256_pd128(q), _mm256_extractf128_pd(q, 1));
  return _mm_cvtsd_f64(_mm_add_sd(h, _mm_unpackhi_pd(h, h)));
}
#endif

#if GRIP_SIMD_AVX512
/// Eight doubles in an AVX-512 register; masks in a k register.
struct PackD8 {
  static constexpr int width = 8;
  struct Mask {
    __mmask8 m;
    friend Mask operator&(Mask a, Mask b) { return {_kand_mask8(a.m, b.m)}; }
    friend Mask operator|(Mask a, Mask b) { return {_kor_mask8(a.m, b.m)}; }
    friend Mask operator!(Mask a) { return {_knot_mask8(a.m)}; }
  };
  __m512d v;
  static PackD8 load(const double* p) { return {_mm512_loadu_pd(p)}; }
  static PackD8 set1(double s) { return {_mm512_set1_pd(s)}; }
  void store(double* p) const { _mm512_storeu_pd(p, v); }
  double sum() const {  // masked extracts: GCC 12 warns on the undefined source of the unmasked ones
    const __m256d z = _mm256_setzero_pd();
    return sum_lanes(_mm256_add_pd(_mm512_mask_extractf64x4_pd(z, 0xFF, v, 0), _mm512_mask_extractf64x4_pd(z, 0xFF, v, 1)));
  }
  /// out[e] = a[e].sum() for 0 <= e < count (count a multiple of 8): eight sums at a time by a
  /// transposing tree of adds, 21 instructions where eight sum() calls take about 64.
  static void sum_each(const PackD8* a, int count, double* out) {
    // Masked forms with a zero source throughout: GCC 12 warns on the undefined source of the
    // unmasked intrinsics (-Wuninitialized).
    const __m512d z = _mm512_setzero_pd();
    const auto pair = [&](__m512d x, __m512d y) {  // lanes (2j, 2j+1): x and y summed over (2j, 2j+1)
      return _mm512_add_pd(_mm512_mask_unpacklo_pd(z, 0xFF, x, y), _mm512_mask_unpackhi_pd(z, 0xFF, x, y));
    };
    const auto halve = [&](__m512d x, __m512d y) {  // 128-bit blocks: x0+x1, x2+x3, y0+y1, y2+y3
      return _mm512_add_pd(_mm512_mask_shuffle_f64x2(z, 0xFF, x, y, 0x88), _mm512_mask_shuffle_f64x2(z, 0xFF, x, y, 0xDD));
    };
    for (int e = 0; e < count; e += 8) {
      const __m512d t = halve(pair(a[e].v, a[e + 1].v), pair(a[e + 2].v, a[e + 3].v));
      const __m512d u = halve(pair(a[e + 4].v, a[e + 5].v), pair(a[e + 6].v, a[e + 7].v));
      _mm512_storeu_pd(out + e, halve(t, u));
    }
  }
  friend PackD8 operator+(PackD8 a, PackD8 b) { return {_mm512_add_pd(a.v, b.v)}; }
  friend PackD8 operator-(PackD8 a, PackD8 b) { return {_mm512_sub_pd(a.v, b.v)}; }
  friend PackD8 operator*(PackD8 a, PackD8 b) { return {_mm512_mul_pd(a.v, b.v)}; }
  friend PackD8 operator/(PackD8 a, PackD8 b) { return {_mm512_div_pd(a.v, b.v)}; }
  friend Mask operator<(PackD8 a, PackD8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LT_OQ)}; }
  friend Mask operator<=(PackD8 a, PackD8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LE_OQ)}; }
  friend Mask operator>(PackD8 a, PackD8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_GT_OQ)}; }
  friend PackD8 select(Mask m, PackD8 a, PackD8 b) { return {_mm512_mask_blend_pd(m.m, b.v, a.v)}; }
  friend PackD8 abs(PackD8 a) { return {_mm512_abs_pd(a.v)}; }
  friend PackD8 sqrt(PackD8 a) { return {_mm512_sqrt_pd(a.v)}; }
  friend PackD8 mul_add(PackD8 a, PackD8 b, PackD8 c) { return {_mm512_fmadd_pd(a.v, b.v, c.v)}; }
  friend PackD8 neg_mul_add(PackD8 a, PackD8 b, PackD8 c) { return {_mm512_fnmadd_pd(a.v, b.v, c.v)}; }
};
#endif

#if GRIP_SIMD_AVX2
/// Four doubles in an AVX register; masks as all-ones lanes.
struct PackD4 {
  static constexpr int width = 4;
  struct Mask {
    __m256d m;
    friend Mask operator&(Mask a, Mask b) { return {_mm256_and_pd(a.m, b.m)}; }
    friend Mask operator|(Mask a, Mask b) { return {_mm256_or_pd(a.m, b.m)}; }
    friend Mask operator!(Mask a) { return {_mm256_xor_pd(a.m, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)))}; }
  };
  __m256d v;
  static PackD4 load(const double* p) { return {_mm256_loadu_pd(p)}; }
  static PackD4 set1(double s) { return {_mm256_set1_pd(s)}; }
  void store(double* p) const { _mm256_storeu_pd(p, v); }
  double sum() const { return sum_lanes(v); }
  /// out[e] = a[e].sum() for 0 <= e < count (count a multiple of 8): four sums at a time.
  static void sum_each(const PackD4* a, int count, double* out) {
    for (int e = 0; e < count; e += 4) {
      const __m256d t0 = _mm256_hadd_pd(a[e].v, a[e + 1].v), t1 = _mm256_hadd_pd(a[e + 2].v, a[e + 3].v);
      _mm256_storeu_pd(out + e, _mm256_add_pd(_mm256_permute2f128_pd(t0, t1, 0x20), _mm256_permute2f128_pd(t0, t1, 0x31)));
    }
  }
  friend PackD4 operator+(PackD4 a, PackD4 b) { return {_mm256_add_pd(a.v, b.v)}; }
  friend PackD4 operator-(PackD4 a, PackD4 b) { return {_mm256_sub_pd(a.v, b.v)}; }
  friend PackD4 operator*(PackD4 a, PackD4 b) { return {_mm256_mul_pd(a.v, b.v)}; }
  friend PackD4 operator/(PackD4 a, PackD4 b) { return {_mm256_div_pd(a.v, b.v)}; }
  friend Mask operator<(PackD4 a, PackD4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ)}; }
  friend Mask operator<=(PackD4 a, PackD4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LE_OQ)}; }
  friend Mask operator>(PackD4 a, PackD4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GT_OQ)}; }
  friend PackD4 select(Mask m, PackD4 a, PackD4 b) { return {_mm256_blendv_pd(b.v, a.v, m.m)}; }
  friend PackD4 abs(PackD4 a) { return {_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)}; }
  friend PackD4 sqrt(PackD4 a) { return {_mm256_sqrt_pd(a.v)}; }
  friend PackD4 mul_add(PackD4 a, PackD4 b, PackD4 c) { return {_mm256_fmadd_pd(a.v, b.v, c.v)}; }
  friend PackD4 neg_mul_add(PackD4 a, PackD4 b, PackD4 c) { return {_mm256_fnmadd_pd(a.v, b.v, c.v)}; }
};
#endif

/// The widest pack compiled in for S.
template <class S>
struct SimdPackOf {
  using type = ScalarPack<S>;
};
#if GRIP_SIMD_AVX512
template <>
struct SimdPackOf<double> {
  using type = PackD8;
};
#elif GRIP_SIMD_AVX2
template <>
struct SimdPackOf<double> {
  using type = PackD4;
};
#endif
template <class S>
using SimdPack = typename SimdPackOf<S>::type;

}  // namespace detail
}  // namespace grip
