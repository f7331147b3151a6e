#pragma once
/// \file
/// The vectorised Coulomb classification of many hard-finger contacts at once, behind
/// StabilityMonitor::classify() and solve_constrained's fast path: eight contacts per step in
/// AVX-512 registers (classify takes a last block of 1 to 4 contacts in 256-bit registers),
/// four with AVX2 + FMA, a portable loop where neither is compiled in.
///
/// Every pass computes, per contact i with force x_i, normal a_i (unit) and friction mu_i:
///   f_n = x_i.a_i,  t = x_i - f_n a_i,  slack = absolute_tolerance + relative_tolerance f_n,
///   lim = mu_i f_n + slack = (mu_i + relative_tolerance) f_n + absolute_tolerance;
///   Separating if !(f_n > 0); else Sliding if lim < 0 or |t|^2 > lim^2; else Sticking;
/// which is CoulombCone::slips() and StabilityMonitor's rule, term by term.
/// solve_constrained's fast path needs less: whether every contact pushes and lies inside or
/// on its cone with no tolerance. coulomb_all_inside answers that alone (no modes, counts,
/// slack or range check), at about half the cost for 3 to 10 contacts. The SIMD passes
/// are taken for double when the translation unit is compiled with AVX-512F and VL (e.g.
/// -march=native on a recent x86-64), else with AVX2 and FMA (-march=x86-64-v3), unless
/// GRIP_NO_SIMD is defined. They read the normals and mu from Grasp::cone_table() (a structure
/// of arrays) and deinterleave the stacked forces in registers. Their range check adds up the
/// contacts' |x|^2 (size_bound) and falls back to the component-by-component check only when a
/// force comes near max_magnitude or holds a NaN. Nothing depends on the CPU at
/// run time: the choice is made by the compiler flags, so a binary runs only where they allow.
/// As with Eigen, compile every translation unit of one program with the same SIMD flags.

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "grip/core/scalar_traits.hpp"
#include "grip/contact/contact_mode.hpp"
#include "grip/core/simd.hpp"


namespace grip {

/// Contacts per step of detail::classify_coulomb for double in this translation unit: 8 with
/// AVX-512, 4 with AVX2 + FMA, 1 for the portable loop (always 1 for float). The modes are the
/// same; only the speed differs.
/// (With AVX-512, grasps of fewer than 8 contacts take the AVX2 pass.)
constexpr int coulomb_kernel_lanes = GRIP_SIMD_AVX512 ? 8 : GRIP_SIMD_AVX2 ? 4 : 1;

namespace detail {

/// What one classification pass counted.
struct CoulombCounts {
  int invalid{0};     ///< > 0 when a force component is NaN, Inf or beyond max_magnitude
  int sliding{0};     ///< contacts in ContactMode::Sliding
  int separating{0};  ///< contacts in ContactMode::Separating
};

/// The portable pass: contacts [0, n) with forces x (3n values, stacked), normals and mu read
/// from the column-major table (columns x, y, z, mu; `stride` rows apart), modes written to
/// modes[0, n). Invalid forces are counted, and their modes are unspecified.
template <class Scalar>
CoulombCounts classify_coulomb_portable(const Scalar* table, int stride, const Scalar* x, int n,
                                        Scalar absolute_tolerance, Scalar relative_tolerance,
                                        ContactMode* modes) {
  CoulombCounts c;
  const Scalar* ax = table;
  const Scalar* ay = table + stride;
  const Scalar* az = table + 2 * stride;
  const Scalar* mu = table + 3 * stride;
  for (int i = 0; i < n; ++i) {
    const Scalar x0 = x[3 * i], x1 = x[3 * i + 1], x2 = x[3 * i + 2];
    constexpr Scalar big = ScalarTraits<Scalar>::max_magnitude;
    c.invalid += int(!(std::abs(x0) <= big)) + int(!(std::abs(x1) <= big)) + int(!(std::abs(x2) <= big));
    const Scalar fn = x0 * ax[i] + x1 * ay[i] + x2 * az[i];
    const Scalar t0 = x0 - fn * ax[i], t1 = x1 - fn * ay[i], t2 = x2 - fn * az[i];
    const Scalar lim = (mu[i] + relative_tolerance) * fn + absolute_tolerance;
    const bool separating = !(fn > Scalar(0));
    const bool sliding = (!separating) & ((lim < Scalar(0)) | (t0 * t0 + t1 * t1 + t2 * t2 > lim * lim));
    modes[i] = static_cast<ContactMode>(2 * int(separating) + int(sliding));
    c.separating += int(separating);
    c.sliding += int(sliding);
  }
  return c;
}

#if GRIP_SIMD_AVX512 || GRIP_SIMD_AVX2
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

/// The part of the rule every SIMD pass shares, for the pack of contacts b .. b + width - 1
/// (PackD8 or PackD4 of core/simd.hpp) with force components fx, fy, fz: their normals loaded
/// from the table (layout as classify_coulomb_portable), f_n = x.a written to `fn`, and
/// |x - f_n a|^2 returned, with fused multiply-adds.
template <class P>
P coulomb_tangent_squared(const double* table, int stride, int b, P fx, P fy, P fz, P& fn) {
  const P nx = P::load(table + b), ny = P::load(table + stride + b), nz = P::load(table + 2 * stride + b);
  fn = mul_add(fz, nz, mul_add(fy, ny, fx * nx));
  const P tx = neg_mul_add(fn, nx, fx), ty = neg_mul_add(fn, ny, fy), tz = neg_mul_add(fn, nz, fz);
  return mul_add(tz, tz, mul_add(ty, ty, tx * tx));
}

/// Loads the stacked forces of 4 contacts into x, y and z lanes, the values 2j, 2j + 1 coming
/// from pair(2j) (an __m128d): pairs 0, 2 and 4 put the (x, y), (z, x) and (y, z) pairs of the
/// first two contacts in the low lanes, pairs 6, 8 and 10 those of the last two in the high
/// lanes; one shuffle per component.
template <class Pair>
GRIP_ALWAYS_INLINE void deinterleave4_pairs(Pair pair, __m256d& fx, __m256d& fy, __m256d& fz) {
  const __m256d q0 = _mm256_insertf128_pd(_mm256_castpd128_pd256(pair(0)), pair(6), 1);
  const __m256d q1 = _mm256_insertf128_pd(_mm256_castpd128_pd256(pair(2)), pair(8), 1);
  const __m256d q2 = _mm256_insertf128_pd(_mm256_castpd128_pd256(pair(4)), pair(10), 1);
  fx = _mm256_shuffle_pd(q0, q1, 0xa);
  fy = _mm256_shuffle_pd(q0, q2, 0x5);
  fz = _mm256_shuffle_pd(q1, q2, 0xa);
}

/// Loads the stacked forces of 4 contacts (12 values from p) into x, y and z lanes.
inline void deinterleave4(const double* p, __m256d& fx, __m256d& fy, __m256d& fz) {
  deinterleave4_pairs([p](int at) { return _mm_loadu_pd(p + at); }, fx, fy, fz);
}
#endif

#if GRIP_SIMD_AVX512
static_assert(static_cast<int>(ContactMode::Sticking) == 0 && static_cast<int>(ContactMode::Sliding) == 1 &&
                  static_cast<int>(ContactMode::Separating) == 2 && sizeof(ContactMode) == 4,
              "the AVX-512 kernel stores modes as 32-bit integers 0, 1, 2");

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

/// Squared magnitudes summed per lane over the blocks of a SIMD pass, f_n^2 + |t|^2 = |x|^2 for
/// each contact (a unit): the pass's cheap range check. At most `size_bound` in every lane
/// proves every component within ScalarTraits<double>::max_magnitude (a component is at most
/// |x|, and the bound leaves room for the round-off of f_n, t and the sum); NaN or anything
/// larger sends the pass to forces_beyond_range(), the exact component-by-component check, so
/// the answer is the portable pass's.
constexpr double size_bound = ScalarTraits<double>::max_magnitude * ScalarTraits<double>::max_magnitude * (1 - 1e-9);

/// The number of the 3n values of x that are NaN, Inf or beyond max_magnitude.
template <class Scalar>
int forces_beyond_range(const Scalar* x, int n) {
  int bad = 0;
  for (int i = 0; i < 3 * n; ++i) bad += int(!(std::abs(x[i]) <= ScalarTraits<Scalar>::max_magnitude));
  return bad;
}

/// Keeps a vector in a register across a loop: without it GCC rebuilds a masked constant from
/// a general register in every step (vpbroadcastd, two operations instead of one move).
template <class V>
inline V in_register(V v) {
#if defined(__GNUC__) || defined(__clang__)
  asm("" : "+v"(v));
#endif
  return v;
}

/// classify_coulomb_avx512's loop. NonNegativeSlack: both tolerances are >= 0, so that
/// lim >= 0 wherever f_n > 0 (mu >= 0 is a Contact invariant) and |t| > lim is t^2 > lim^2.
template <int FixedN, bool NonNegativeSlack>
GRIP_ALWAYS_INLINE CoulombCounts classify_coulomb_avx512_pass(const double* table, int stride, const double* x,
                                                              int n_runtime, double absolute_tolerance,
                                                              double relative_tolerance, ContactMode* modes) {
  const int n = FixedN > 0 ? FixedN : n_runtime;
  const Deinterleave8 split;
  const __m512d abs_mask = _mm512_castsi512_pd(_mm512_set1_epi64(0x7fffffffffffffffLL));
  const __m512d tol_abs = _mm512_set1_pd(absolute_tolerance);
  const __m512d tol_rel = _mm512_set1_pd(relative_tolerance);
  const __m512d zero = _mm512_setzero_pd();
  const __m256i one = in_register(_mm256_set1_epi32(1)), two = in_register(_mm256_set1_epi32(2));
  CoulombCounts c;
  __m512d size = _mm512_setzero_pd();  // per lane, the sum of |x|^2 (see size_bound)
  // A last block of 1 to 4 contacts takes 256-bit registers (below): half the work.
  const int blocks_end = n % 8 != 0 && n % 8 <= 4 ? n - n % 8 : n;
  for (int b = 0; b < blocks_end; b += 8) {
    const __mmask8 lanes = low_lanes(n - b);
    __m512d fx, fy, fz;
    split.load(x + 3 * b, n - b, fx, fy, fz);
    const __m512d mu = _mm512_add_pd(_mm512_loadu_pd(table + 3 * stride + b), tol_rel);
    PackD8 fn_pack{};
    const __m512d t2 = coulomb_tangent_squared(table, stride, b, PackD8{fx}, PackD8{fy}, PackD8{fz}, fn_pack).v;
    const __m512d fn = fn_pack.v;
    size = _mm512_add_pd(size, _mm512_fmadd_pd(fn, fn, t2));
    // lim = (mu + relative_tolerance) f_n + absolute_tolerance; the slack is the last two terms.
    const __m512d lim = _mm512_fmadd_pd(mu, fn, tol_abs);
    const __mmask8 separating = _mm512_mask_cmp_pd_mask(lanes, fn, zero, _CMP_NGT_UQ);
    // |t| > lim, squared with the sign kept: t^2 > lim |lim| (always true for lim < 0).
    const __m512d lim_squared = _mm512_mul_pd(lim, NonNegativeSlack ? lim : _mm512_and_pd(lim, abs_mask));
    const __mmask8 over = _mm512_mask_cmp_pd_mask(lanes, t2, lim_squared, _CMP_GT_OQ);
    // Sliding where over and not separating: separating's 2 is written over over's 1.
    _mm256_mask_storeu_epi32(modes + b, lanes, _mm256_mask_mov_epi32(_mm256_maskz_mov_epi32(over, one), separating, two));
    const unsigned separating_bits = static_cast<unsigned>(separating);
    c.separating += bit_count(separating_bits);
    c.sliding += bit_count(static_cast<unsigned>(over) & ~separating_bits);
  }
  __mmask8 beyond = _mm512_cmp_pd_mask(size, _mm512_set1_pd(size_bound), _CMP_NLE_UQ);
  if (blocks_end < n) {  // the same rule on 4 lanes
    const int b = blocks_end;
    const __mmask8 lanes = low_lanes(n - b);
    __m256d fx, fy, fz;
    deinterleave4_masked(x + 3 * b, n - b, fx, fy, fz);
    const __m256d mu = _mm256_add_pd(_mm256_loadu_pd(table + 3 * stride + b), _mm512_castpd512_pd256(tol_rel));
    PackD4 fn_pack{};
    const __m256d t2 = coulomb_tangent_squared(table, stride, b, PackD4{fx}, PackD4{fy}, PackD4{fz}, fn_pack).v;
    const __m256d fn = fn_pack.v;
    beyond |= _mm256_cmp_pd_mask(_mm256_fmadd_pd(fn, fn, t2), _mm512_castpd512_pd256(_mm512_set1_pd(size_bound)), _CMP_NLE_UQ);
    const __m256d lim = _mm256_fmadd_pd(mu, fn, _mm512_castpd512_pd256(tol_abs));
    const __mmask8 separating = _mm256_mask_cmp_pd_mask(lanes, fn, _mm256_setzero_pd(), _CMP_NGT_UQ);
    const __m256d lim_squared =
        _mm256_mul_pd(lim, NonNegativeSlack ? lim : _mm256_and_pd(lim, _mm512_castpd512_pd256(abs_mask)));
    const __mmask8 over = _mm256_mask_cmp_pd_mask(lanes, t2, lim_squared, _CMP_GT_OQ);
    _mm_mask_storeu_epi32(modes + b, lanes, _mm_mask_mov_epi32(_mm_maskz_mov_epi32(over, _mm256_castsi256_si128(one)),
                                                               separating, _mm256_castsi256_si128(two)));
    const unsigned separating_bits = static_cast<unsigned>(separating);
    c.separating += bit_count(separating_bits);
    c.sliding += bit_count(static_cast<unsigned>(over) & ~separating_bits);
  }
  if (beyond != 0) c.invalid = forces_beyond_range(x, n);
  return c;
}

/// The AVX-512 pass, same contract as classify_coulomb_portable<double>. Precondition: the
/// table has at least n rounded up to a multiple of 8 rows (Grasp::padded_capacity); modes
/// has room for n entries (only [0, n) is written), x for 3n values (only those are read).
/// FixedN > 0: n == FixedN known at compile time (the loop unrolls, the lane masks fold).
template <int FixedN = 0>
GRIP_ALWAYS_INLINE CoulombCounts classify_coulomb_avx512(const double* table, int stride, const double* x, int n_runtime,
                                                          double absolute_tolerance, double relative_tolerance,
                                                          ContactMode* modes) {
  if (absolute_tolerance >= 0 && relative_tolerance >= 0)
    return classify_coulomb_avx512_pass<FixedN, true>(table, stride, x, n_runtime, absolute_tolerance,
                                                      relative_tolerance, modes);
  return classify_coulomb_avx512_pass<FixedN, false>(table, stride, x, n_runtime, absolute_tolerance,
                                                     relative_tolerance, modes);
}

#endif

#if GRIP_SIMD_AVX2
/// Per 4-bit mask, the 4 lanes of 32-bit modes it stands for, times `value` (1 or 2).
struct ModeLanes {
  alignas(16) std::int32_t lane[16][4];
  constexpr explicit ModeLanes(std::int32_t value) : lane{} {
    for (int m = 0; m < 16; ++m)
      for (int k = 0; k < 4; ++k) lane[m][k] = (m >> k) & 1 ? value : 0;
  }
};

/// The AVX2 + FMA pass (4 contacts per step, 256-bit registers), same contract as
/// classify_coulomb_portable<double>; a last partial step of fewer than 4 contacts runs the
/// portable loop. Precondition as classify_coulomb_avx512.
template <int FixedN = 0>
GRIP_ALWAYS_INLINE CoulombCounts classify_coulomb_avx2(const double* table, int stride, const double* x, int n_runtime,
                                    double absolute_tolerance, double relative_tolerance, ContactMode* modes) {
  static constexpr ModeLanes sliding_lanes{1}, separating_lanes{2};
  const int n = FixedN > 0 ? FixedN : n_runtime;
  const __m256d abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
  const __m256d big = _mm256_set1_pd(ScalarTraits<double>::max_magnitude);
  const __m256d tol_abs = _mm256_set1_pd(absolute_tolerance);
  const __m256d tol_rel = _mm256_set1_pd(relative_tolerance);
  const __m256d zero = _mm256_setzero_pd();
  __m256d invalid = _mm256_setzero_pd();
  CoulombCounts c;
  int b = 0;
  for (; b + 4 <= n; b += 4) {
    __m256d fx, fy, fz;
    deinterleave4(x + 3 * b, fx, fy, fz);
    const __m256d mu = _mm256_loadu_pd(table + 3 * stride + b);
    const __m256d bx = _mm256_and_pd(fx, abs_mask), by = _mm256_and_pd(fy, abs_mask), bz = _mm256_and_pd(fz, abs_mask);
    invalid = _mm256_or_pd(invalid, _mm256_or_pd(_mm256_cmp_pd(bx, big, _CMP_NLE_UQ),
                                                 _mm256_or_pd(_mm256_cmp_pd(by, big, _CMP_NLE_UQ),
                                                              _mm256_cmp_pd(bz, big, _CMP_NLE_UQ))));
    PackD4 fn_pack{};
    const __m256d t2 = coulomb_tangent_squared(table, stride, b, PackD4{fx}, PackD4{fy}, PackD4{fz}, fn_pack).v;
    const __m256d fn = fn_pack.v;
    const __m256d lim = _mm256_fmadd_pd(_mm256_add_pd(mu, tol_rel), fn, tol_abs);
    const int separating = _mm256_movemask_pd(_mm256_cmp_pd(fn, zero, _CMP_NGT_UQ));
    const int over = _mm256_movemask_pd(_mm256_cmp_pd(t2, _mm256_mul_pd(lim, _mm256_and_pd(lim, abs_mask)), _CMP_GT_OQ));
    const int sliding = over & ~separating;
    const __m128i mode = _mm_or_si128(_mm_load_si128(reinterpret_cast<const __m128i*>(separating_lanes.lane[separating])),
                                      _mm_load_si128(reinterpret_cast<const __m128i*>(sliding_lanes.lane[sliding])));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(modes + b), mode);
    c.separating += bit_count(static_cast<unsigned>(separating));
    c.sliding += bit_count(static_cast<unsigned>(sliding));
  }
  c.invalid = _mm256_movemask_pd(invalid);
  if (b < n) {
    const CoulombCounts tail = classify_coulomb_portable(table + b, stride, x + 3 * b, n - b, absolute_tolerance,
                                                         relative_tolerance, modes + b);
    c.invalid += tail.invalid;
    c.sliding += tail.sliding;
    c.separating += tail.separating;
  }
  return c;
}
#endif

/// The pass for this translation unit, for double: AVX-512 from 8 contacts on, else AVX2
/// (whole blocks of 4, the rest portable), else the portable loop; always portable for float.
/// FixedN: the grasp's compile-time contact count (n == FixedN), or 0 (Dynamic).
template <int FixedN, class Scalar>
GRIP_ALWAYS_INLINE CoulombCounts classify_coulomb(const Scalar* table, int stride, const Scalar* x, int n, Scalar absolute_tolerance,
                               Scalar relative_tolerance, ContactMode* modes) {
  if constexpr (std::is_same<Scalar, double>::value) {
#if GRIP_SIMD_AVX512
    // Below one full block, 256-bit code is as fast, and it spares the core the wake-up of its
    // 512-bit units (measured: the first 512-bit pass after other code runs slower).
    if ((FixedN > 0 ? FixedN : n) >= 8)
      return classify_coulomb_avx512<FixedN>(table, stride, x, n, absolute_tolerance, relative_tolerance, modes);
#endif
#if GRIP_SIMD_AVX2
    return classify_coulomb_avx2<FixedN>(table, stride, x, n, absolute_tolerance, relative_tolerance, modes);
#endif
  }
  return classify_coulomb_portable(table, stride, x, n, absolute_tolerance, relative_tolerance, modes);
}

/// classify_coulomb over a whole hard-finger grasp (any Grasp type): its cone_table(), its
/// size (compile-time when fixed) and its stacked forces x (grasp.unknowns() values).
template <class GraspT, class Forces>
GRIP_ALWAYS_INLINE CoulombCounts classify_coulomb_grasp(const GraspT& grasp, const Forces& x,
                                     typename GraspT::ScalarType absolute_tolerance,
                                     typename GraspT::ScalarType relative_tolerance, ContactMode* modes) {
  static_assert(GraspT::dim == 3, "the Coulomb pass is for hard fingers");
  return classify_coulomb<(GraspT::fixed_size > 0 ? GraspT::fixed_size : 0)>(
      grasp.cone_table().data(), GraspT::padded_capacity, x.data(), grasp.size(), absolute_tolerance,
      relative_tolerance, modes);
}

/// True when every contact i in [0, n) pushes and lies inside or on its cone with no
/// tolerance: f_n = x_i.a_i > 0 and |x_i - f_n a_i|^2 <= (mu_i f_n)^2, i.e. CoulombCone's
/// `normal_part(x) > 0 && !slips(x, 0)` (solve_constrained's fast-path test). A NaN force
/// fails; no other check of the values (a finite force beyond max_magnitude may pass). The
/// lean form of classify_coulomb: no modes, counts or slack. Table layout as
/// classify_coulomb_portable.
template <class Scalar>
bool coulomb_all_inside_portable(const Scalar* table, int stride, const Scalar* x, int n) {
  bool inside = true;
  for (int i = 0; i < n; ++i) {
    const Scalar ax = table[i], ay = table[stride + i], az = table[2 * stride + i];
    const Scalar x0 = x[3 * i], x1 = x[3 * i + 1], x2 = x[3 * i + 2];
    const Scalar fn = x0 * ax + x1 * ay + x2 * az;
    const Scalar t0 = x0 - fn * ax, t1 = x1 - fn * ay, t2 = x2 - fn * az;
    const Scalar lim = table[3 * stride + i] * fn;
    inside = inside & (fn > Scalar(0)) & (t0 * t0 + t1 * t1 + t2 * t2 <= lim * lim);
  }
  return inside;
}

#if GRIP_SIMD_AVX512
/// coulomb_all_inside_portable<double>, 8 contacts per step, the last step masked (any n).
/// Precondition as classify_coulomb_avx512.
template <int FixedN = 0>
bool coulomb_all_inside_avx512(const double* table, int stride, const double* x, int n_runtime) {
  const int n = FixedN > 0 ? FixedN : n_runtime;
  const Deinterleave8 split;
  const __m512d zero = _mm512_setzero_pd();
  unsigned outside = 0;
  for (int b = 0; b < n; b += 8) {
    __m512d fx, fy, fz;
    split.load(x + 3 * b, n - b, fx, fy, fz);
    PackD8 fn_pack{};
    const __m512d t2 = coulomb_tangent_squared(table, stride, b, PackD8{fx}, PackD8{fy}, PackD8{fz}, fn_pack).v;
    const __m512d fn = fn_pack.v;
    const __m512d lim = _mm512_mul_pd(_mm512_loadu_pd(table + 3 * stride + b), fn);
    const __mmask8 lanes = low_lanes(n - b);
    const __mmask8 pushing = _mm512_mask_cmp_pd_mask(lanes, fn, zero, _CMP_GT_OQ);
    const __mmask8 inside = _mm512_mask_cmp_pd_mask(pushing, t2, _mm512_mul_pd(lim, lim), _CMP_LE_OQ);
    outside |= static_cast<unsigned>(lanes) & ~static_cast<unsigned>(inside);
  }
  return outside == 0;
}
#endif

#if GRIP_SIMD_AVX2
/// coulomb_all_inside_portable<double>, 4 contacts per step, a last partial step portable.
template <int FixedN = 0>
bool coulomb_all_inside_avx2(const double* table, int stride, const double* x, int n_runtime) {
  const int n = FixedN > 0 ? FixedN : n_runtime;
  const __m256d zero = _mm256_setzero_pd();
  __m256d inside = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  int b = 0;
  for (; b + 4 <= n; b += 4) {
    __m256d fx, fy, fz;
    deinterleave4(x + 3 * b, fx, fy, fz);
    PackD4 fn_pack{};
    const __m256d t2 = coulomb_tangent_squared(table, stride, b, PackD4{fx}, PackD4{fy}, PackD4{fz}, fn_pack).v;
    const __m256d fn = fn_pack.v;
    const __m256d lim = _mm256_mul_pd(_mm256_loadu_pd(table + 3 * stride + b), fn);
    inside = _mm256_and_pd(inside, _mm256_and_pd(_mm256_cmp_pd(fn, zero, _CMP_GT_OQ),
                                                 _mm256_cmp_pd(t2, _mm256_mul_pd(lim, lim), _CMP_LE_OQ)));
  }
  return _mm256_movemask_pd(inside) == 0xf &&
         coulomb_all_inside_portable(table + b, stride, x + 3 * b, n - b);
}
#endif

/// coulomb_all_inside_portable through this translation unit's widest pass for double
/// (AVX-512 from 8 contacts on, else AVX2), the portable loop for float. FixedN as classify_coulomb.
template <int FixedN, class Scalar>
bool coulomb_all_inside(const Scalar* table, int stride, const Scalar* x, int n) {
  if constexpr (std::is_same<Scalar, double>::value) {
#if GRIP_SIMD_AVX512
    // As in classify_coulomb: below one full block the 256-bit pass is as fast.
    if ((FixedN > 0 ? FixedN : n) >= 8) return coulomb_all_inside_avx512<FixedN>(table, stride, x, n);
#endif
#if GRIP_SIMD_AVX2
    return coulomb_all_inside_avx2<FixedN>(table, stride, x, n);
#endif
  }
  return coulomb_all_inside_portable(table, stride, x, n);
}

/// coulomb_all_inside over a whole hard-finger grasp and its stacked forces x.
template <class GraspT, class Forces>
bool coulomb_all_inside_grasp(const GraspT& grasp, const Forces& x) {
  static_assert(GraspT::dim == 3, "the Coulomb pass is for hard fingers");
  return coulomb_all_inside<(GraspT::fixed_size > 0 ? GraspT::fixed_size : 0)>(
      grasp.cone_table().data(), GraspT::padded_capacity, x.data(), grasp.size());
}

}  // namespace detail
}  // namespace grip
