#pragma once
/// \file
/// Which SIMD instructions grip's vectorised passes use in this translation unit, chosen by the
/// compiler flags (nothing is detected at run time): GRIP_SIMD_AVX512 (AVX-512F and VL, e.g.
/// -march=native on a recent x86-64, or -march=x86-64-v4), GRIP_SIMD_AVX2 (AVX2 and FMA,
/// -march=x86-64-v3), each 1 or 0; defining GRIP_NO_SIMD turns both off. As with Eigen, compile every translation unit
/// of one program with the same SIMD flags.

#include <cmath>
#include <cstdint>
#include <type_traits>

/// Marks a function the compiler must inline (the SIMD passes into their callers, where their
/// small results stay in registers), except where the build optimises for size (-Os,
/// __OPTIMIZE_SIZE__: a microcontroller's flash), which leaves the choice to the compiler.
#if (defined(__GNUC__) || defined(__clang__)) && !defined(__OPTIMIZE_SIZE__)
#define GRIP_ALWAYS_INLINE inline __attribute__((always_inline))
#elif defined(_MSC_VER)
#define GRIP_ALWAYS_INLINE __forceinline
#else
#define GRIP_ALWAYS_INLINE inline
#endif

/// GRIP_UNROLL(n), written before a loop of at most n iterations: unrolls it fully where the
/// build optimises for speed (a pass's sums then stay in registers), and leaves it a loop where
/// it optimises for size (-Os, __OPTIMIZE_SIZE__: a microcontroller's flash).
#if (defined(__GNUC__) || defined(__clang__)) && !defined(__OPTIMIZE_SIZE__)
#define GRIP_DETAIL_PRAGMA(text) _Pragma(#text)
#define GRIP_UNROLL(n) GRIP_DETAIL_PRAGMA(GCC unroll n)
#else
#define GRIP_UNROLL(n)
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
/// AVX-512, 4 with AVX2. For kernels over stacked 3-vectors (contact/coulomb_kernel.hpp) every
/// pack also has load_xyz, store_codes and first(k); PackD8, and PackD4 with AVX-512, have the
/// masked forms taking k, the lanes in use, for a last partial block.
template <class S>
struct ScalarPack {
  using Scalar = S;
  static constexpr int width = 1;
  /// A lane-wise truth value: combine with &, |, !, and_not (a & !b); bits() has bit j set
  /// where lane j is true, count() the number of true lanes.
  struct Mask {
    bool m;
    // Bitwise, not && and ||: no branches (lanes of neighbouring contacts are not predictable).
    friend Mask operator&(Mask a, Mask b) { return {static_cast<bool>(a.m & b.m)}; }
    friend Mask operator|(Mask a, Mask b) { return {static_cast<bool>(a.m | b.m)}; }
    friend Mask operator!(Mask a) { return {!a.m}; }
    friend Mask and_not(Mask a, Mask b) { return {static_cast<bool>(a.m & !b.m)}; }
    unsigned bits() const { return m ? 1u : 0u; }
    int count() const { return m ? 1 : 0; }
  };
  S v;
  /// The first k lanes true (k clamped to [0, width]).
  static Mask first(int k) { return {k > 0}; }
  /// Lanes j of x, y, z from p[3j], p[3j + 1], p[3j + 2]: `width` stacked 3-vectors deinterleaved.
  static void load_xyz(const S* p, ScalarPack& x, ScalarPack& y, ScalarPack& z) {
    x = {p[0]};
    y = {p[1]};
    z = {p[2]};
  }
  /// Writes per lane j the code 2 where twos, 1 where ones, else 0 (ones and twos disjoint) to
  /// p[j], a 32-bit integer or enumeration (e.g. ContactMode).
  template <class Out>
  static void store_codes(Out* p, Mask ones, Mask twos) {
    static_assert(sizeof(Out) == 4, "32-bit codes");
    *p = static_cast<Out>(2 * int(twos.m) + int(ones.m));
  }
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
  /// !(a > b): true where a <= b or either is NaN.
  friend Mask not_greater(ScalarPack a, ScalarPack b) { return {!(a.v > b.v)}; }
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

/// Number of set bits of a lane mask of at most 8 lanes (a SIMD compare's result).
inline int bit_count(unsigned m) {
#if defined(__POPCNT__)
  return _mm_popcnt_u32(m);
#else
  m = m - ((m >> 1) & 0x55u);
  m = (m & 0x33u) + ((m >> 2) & 0x33u);
  return static_cast<int>((m + (m >> 4)) & 0x0fu);
#endif
}

/// Loads the stacked 3-vectors of 4 contacts into x, y and z lanes, the values 2j, 2j + 1
/// coming from pair(2j) (an __m128d): pairs 0, 2 and 4 put the (x, y), (z, x) and (y, z) pairs
/// of the first two contacts in the low lanes, pairs 6, 8 and 10 those of the last two in the
/// high lanes; one shuffle per component.
template <class Pair>
GRIP_ALWAYS_INLINE void deinterleave4_pairs(Pair pair, __m256d& fx, __m256d& fy, __m256d& fz) {
  const __m256d q0 = _mm256_insertf128_pd(_mm256_castpd128_pd256(pair(0)), pair(6), 1);
  const __m256d q1 = _mm256_insertf128_pd(_mm256_castpd128_pd256(pair(2)), pair(8), 1);
  const __m256d q2 = _mm256_insertf128_pd(_mm256_castpd128_pd256(pair(4)), pair(10), 1);
  fx = _mm256_shuffle_pd(q0, q1, 0xa);
  fy = _mm256_shuffle_pd(q0, q2, 0x5);
  fz = _mm256_shuffle_pd(q1, q2, 0xa);
}

/// Loads the stacked 3-vectors of 4 contacts (12 values from p) into x, y and z lanes.
inline void deinterleave4(const double* p, __m256d& fx, __m256d& fy, __m256d& fz) {
  deinterleave4_pairs([p](int at) { return _mm_loadu_pd(p + at); }, fx, fy, fz);
}

/// Per 4-bit mask, the 4 lanes of 32-bit codes it stands for, times `value` (1 or 2).
struct ModeLanes {
  alignas(16) std::int32_t lane[16][4];
  constexpr explicit ModeLanes(std::int32_t value) : lane{} {
    for (int m = 0; m < 16; ++m)
      for (int k = 0; k < 4; ++k) lane[m][k] = (m >> k) & 1 ? value : 0;
  }
};

/// PackD4's codes (see ScalarPack::store_codes) for lane bits `ones` and `twos`, from two tables.
inline __m128i code_lanes(unsigned ones, unsigned twos) {
  static constexpr ModeLanes one_lanes{1}, two_lanes{2};
  return _mm_or_si128(_mm_load_si128(reinterpret_cast<const __m128i*>(two_lanes.lane[twos])),
                      _mm_load_si128(reinterpret_cast<const __m128i*>(one_lanes.lane[ones])));
}
#endif

#if GRIP_SIMD_AVX512
/// The lowest k bits set (k clamped to [0, 8]).
inline __mmask8 low_lanes(int k) {
  return static_cast<__mmask8>(k >= 8 ? 0xffu : k <= 0 ? 0u : (1u << static_cast<unsigned>(k)) - 1u);
}

/// Loads the stacked forces of contacts b .. b + 7 (24 values from p; only the first 3 k are
/// read, k = contacts left, and lanes k .. 7 come out zero) into x, y and z lanes. The values
/// arrive in three registers, v0 = (x0 y0 z0 x1 y1 z1 x2 y2), v1 = (z2 x3 y3 z3 x4 y4 z4 x5),
/// v2 = (y5 z5 x6 y6 z6 x7 y7 z7): each component fills lanes {0, 3, 6} of one register,
/// {1, 4, 7} of the next and {2, 5} of the third, so two blends gather its eight values (x in
/// the contact order 0 3 6 1 4 7 2 5, y and z the same rotated by one and two lanes) and one
/// one-source permute puts them in contact order: 6 blends and 3 permutes, where two-source
/// permutes took 6.
struct Deinterleave8 {
  static constexpr __mmask8 lanes_036 = 0x49, lanes_147 = 0x92, lanes_25 = 0x24;
  __m512i order_x = _mm512_setr_epi64(0, 3, 6, 1, 4, 7, 2, 5);
  __m512i order_y = _mm512_setr_epi64(1, 4, 7, 2, 5, 0, 3, 6);
  __m512i order_z = _mm512_setr_epi64(2, 5, 0, 3, 6, 1, 4, 7);

  void load(const double* p, int k, __m512d& fx, __m512d& fy, __m512d& fz) const {
    const int values = 3 * k;
    const __m512d v0 = _mm512_maskz_loadu_pd(low_lanes(values), p);
    const __m512d v1 = _mm512_maskz_loadu_pd(low_lanes(values - 8), p + 8);
    const __m512d v2 = _mm512_maskz_loadu_pd(low_lanes(values - 16), p + 16);
    // Zero-masked permutes with every lane kept: the same vpermpd as the plain intrinsic, whose
    // undefined source g++ 12 reports as used uninitialized.
    constexpr __mmask8 all = 0xFF;
    const __m512d gx = _mm512_mask_mov_pd(_mm512_mask_mov_pd(v2, lanes_036, v0), lanes_147, v1);
    const __m512d gy = _mm512_mask_mov_pd(_mm512_mask_mov_pd(v2, lanes_147, v0), lanes_25, v1);
    const __m512d gz = _mm512_mask_mov_pd(_mm512_mask_mov_pd(v2, lanes_25, v0), lanes_036, v1);
    fx = _mm512_maskz_permutexvar_pd(all, order_x, gx);
    fy = _mm512_maskz_permutexvar_pd(all, order_y, gy);
    fz = _mm512_maskz_permutexvar_pd(all, order_z, gz);
  }
};

/// deinterleave4 for at most 4 contacts (only the first 3 k of the 12 values read, lanes
/// k .. 3 zero): the AVX-512 pass's last block.
inline void deinterleave4_masked(const double* p, int k, __m256d& fx, __m256d& fy, __m256d& fz) {
  const int values = 3 * k;
  deinterleave4_pairs([p, values](int at) { return _mm_maskz_loadu_pd(low_lanes(values - at), p + at); }, fx, fy, fz);
}
#endif

#if GRIP_SIMD_AVX512
/// Eight doubles in an AVX-512 register; masks in a k register.
struct PackD8 {
  using Scalar = double;
  static constexpr int width = 8;
  struct Mask {
    __mmask8 m;
    friend Mask operator&(Mask a, Mask b) { return {_kand_mask8(a.m, b.m)}; }
    friend Mask operator|(Mask a, Mask b) { return {_kor_mask8(a.m, b.m)}; }
    friend Mask operator!(Mask a) { return {_knot_mask8(a.m)}; }
    friend Mask and_not(Mask a, Mask b) { return {static_cast<__mmask8>(a.m & ~b.m)}; }
    unsigned bits() const { return m; }
    int count() const { return bit_count(m); }
  };
  __m512d v;
  static Mask first(int k) { return {low_lanes(k)}; }
  /// ScalarPack::load_xyz for the first k contacts (only 3 k values read; lanes k .. 7 zero).
  static void load_xyz(const double* p, int k, PackD8& x, PackD8& y, PackD8& z) {
    const Deinterleave8 split;
    split.load(p, k, x.v, y.v, z.v);
  }
  static void load_xyz(const double* p, PackD8& x, PackD8& y, PackD8& z) { load_xyz(p, 8, x, y, z); }
  /// ScalarPack::store_codes for the first k lanes (k clamped to [0, 8]; p[k ..] untouched).
  template <class Out>
  static void store_codes(Out* p, int k, Mask ones, Mask twos) {
    static_assert(sizeof(Out) == 4, "32-bit codes");
    // 1 in the lanes of ones and twos (all-ones shifted), doubled in those of twos: no
    // constant but all-ones, which compilers make in place (a constant 1 or 2 g++ rebuilds
    // from a general register in every step of a loop).
    const __m256i one = _mm256_maskz_srli_epi32(static_cast<__mmask8>(ones.m | twos.m), _mm256_set1_epi32(-1), 31);
    const __m256i code = _mm256_mask_add_epi32(one, twos.m, one, one);
    _mm256_mask_storeu_epi32(p, low_lanes(k), code);
  }
  template <class Out>
  static void store_codes(Out* p, Mask ones, Mask twos) {
    store_codes(p, 8, ones, twos);
  }
  static PackD8 load(const double* p) { return {_mm512_loadu_pd(p)}; }
  static PackD8 set1(double s) { return {_mm512_set1_pd(s)}; }
  void store(double* p) const { _mm512_storeu_pd(p, v); }
  double sum() const {  // masked extracts: GCC 12 warns on the undefined source of the unmasked ones
    const __m256d z = _mm256_setzero_pd();
    return sum_lanes(
        _mm256_add_pd(_mm512_mask_extractf64x4_pd(z, 0xFF, v, 0), _mm512_mask_extractf64x4_pd(z, 0xFF, v, 1)));
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
      return _mm512_add_pd(_mm512_mask_shuffle_f64x2(z, 0xFF, x, y, 0x88),
                           _mm512_mask_shuffle_f64x2(z, 0xFF, x, y, 0xDD));
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
  friend Mask not_greater(PackD8 a, PackD8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_NGT_UQ)}; }
  friend PackD8 select(Mask m, PackD8 a, PackD8 b) { return {_mm512_mask_blend_pd(m.m, b.v, a.v)}; }
  friend PackD8 abs(PackD8 a) { return {_mm512_abs_pd(a.v)}; }
  // Masked with every lane kept: GCC 12's unmasked intrinsic reads an undefined source (-Wuninitialized).
  friend PackD8 sqrt(PackD8 a) { return {_mm512_maskz_sqrt_pd(0xFF, a.v)}; }
  friend PackD8 mul_add(PackD8 a, PackD8 b, PackD8 c) { return {_mm512_fmadd_pd(a.v, b.v, c.v)}; }
  friend PackD8 neg_mul_add(PackD8 a, PackD8 b, PackD8 c) { return {_mm512_fnmadd_pd(a.v, b.v, c.v)}; }
};
#endif

#if GRIP_SIMD_AVX2
/// Four doubles in an AVX register; masks as all-ones lanes.
struct PackD4 {
  using Scalar = double;
  static constexpr int width = 4;
  struct Mask {
    __m256d m;
    friend Mask operator&(Mask a, Mask b) { return {_mm256_and_pd(a.m, b.m)}; }
    friend Mask operator|(Mask a, Mask b) { return {_mm256_or_pd(a.m, b.m)}; }
    friend Mask operator!(Mask a) { return {_mm256_xor_pd(a.m, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)))}; }
    friend Mask and_not(Mask a, Mask b) { return {_mm256_andnot_pd(b.m, a.m)}; }
    unsigned bits() const { return static_cast<unsigned>(_mm256_movemask_pd(m)); }
    int count() const { return bit_count(bits()); }
  };
  __m256d v;
  static Mask first(int k) {
    return {_mm256_castsi256_pd(_mm256_cmpgt_epi64(_mm256_set1_epi64x(k), _mm256_setr_epi64x(0, 1, 2, 3)))};
  }
  static void load_xyz(const double* p, PackD4& x, PackD4& y, PackD4& z) { deinterleave4(p, x.v, y.v, z.v); }
  template <class Out>
  static void store_codes(Out* p, Mask ones, Mask twos) {
    static_assert(sizeof(Out) == 4, "32-bit codes");
    _mm_storeu_si128(reinterpret_cast<__m128i*>(p), code_lanes(ones.bits(), twos.bits()));
  }
#if GRIP_SIMD_AVX512
  /// The masked forms (AVX-512VL), as PackD8's: the AVX-512 pass's last block of 1 to 4 contacts.
  static void load_xyz(const double* p, int k, PackD4& x, PackD4& y, PackD4& z) {
    deinterleave4_masked(p, k, x.v, y.v, z.v);
  }
  template <class Out>
  static void store_codes(Out* p, int k, Mask ones, Mask twos) {
    static_assert(sizeof(Out) == 4, "32-bit codes");
    _mm_mask_storeu_epi32(p, low_lanes(k), code_lanes(ones.bits(), twos.bits()));
  }
#endif
  static PackD4 load(const double* p) { return {_mm256_loadu_pd(p)}; }
  static PackD4 set1(double s) { return {_mm256_set1_pd(s)}; }
  void store(double* p) const { _mm256_storeu_pd(p, v); }
  double sum() const { return sum_lanes(v); }
  /// out[e] = a[e].sum() for 0 <= e < count (count a multiple of 8): four sums at a time.
  static void sum_each(const PackD4* a, int count, double* out) {
    for (int e = 0; e < count; e += 4) {
      const __m256d t0 = _mm256_hadd_pd(a[e].v, a[e + 1].v), t1 = _mm256_hadd_pd(a[e + 2].v, a[e + 3].v);
      _mm256_storeu_pd(out + e,
                       _mm256_add_pd(_mm256_permute2f128_pd(t0, t1, 0x20), _mm256_permute2f128_pd(t0, t1, 0x31)));
    }
  }
  friend PackD4 operator+(PackD4 a, PackD4 b) { return {_mm256_add_pd(a.v, b.v)}; }
  friend PackD4 operator-(PackD4 a, PackD4 b) { return {_mm256_sub_pd(a.v, b.v)}; }
  friend PackD4 operator*(PackD4 a, PackD4 b) { return {_mm256_mul_pd(a.v, b.v)}; }
  friend PackD4 operator/(PackD4 a, PackD4 b) { return {_mm256_div_pd(a.v, b.v)}; }
  friend Mask operator<(PackD4 a, PackD4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ)}; }
  friend Mask operator<=(PackD4 a, PackD4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LE_OQ)}; }
  friend Mask operator>(PackD4 a, PackD4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GT_OQ)}; }
  friend Mask not_greater(PackD4 a, PackD4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_NGT_UQ)}; }
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

/// The pack of a pass over at most Cap items (contacts): SimdPack<S>, except that with AVX-512 at
/// most 4 items take PackD4. One block then holds them all at half the width: the pass's
/// per-lane sums cost half as much to clear and to add across the lanes.
template <class S, int Cap>
struct SimdPackForOf {
  using type = SimdPack<S>;
};
#if GRIP_SIMD_AVX512 && GRIP_SIMD_AVX2
template <int Cap>
struct SimdPackForOf<double, Cap> {
  using type = typename std::conditional<(Cap >= 0 && Cap <= 4), PackD4, PackD8>::type;
};
#endif
template <class S, int Cap>
using SimdPackFor = typename SimdPackForOf<S, Cap>::type;

}  // namespace detail
}  // namespace grip
