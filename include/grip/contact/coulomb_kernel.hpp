#pragma once
/// \file
/// The vectorised Coulomb classification of many hard-finger contacts at once, behind
/// StabilityMonitor::classify() and solve_constrained's fast path: eight contacts per step in
/// AVX-512 registers (classify takes a last block of 1 to 4 contacts in 256-bit registers),
/// four with AVX2 + FMA, one at a time where neither is compiled in.
///
/// Every pass computes, per contact i with force x_i, normal a_i (unit) and friction mu_i:
///   f_n = x_i.a_i,  t = x_i - f_n a_i,  slack = absolute_tolerance + relative_tolerance f_n,
///   lim = mu_i f_n + slack = (mu_i + relative_tolerance) f_n + absolute_tolerance;
///   Separating if !(f_n > 0); else Sliding if lim < 0 or |t|^2 > lim^2; else Sticking;
/// which is CoulombCone::slips() and StabilityMonitor's rule, term by term.
/// solve_constrained's fast path needs less: whether every contact pushes and lies inside or
/// on its cone with no tolerance. coulomb_all_inside answers that alone (no modes, counts,
/// slack or range check), at about half the cost for 3 to 10 contacts.
///
/// Each rule is written once, over the packs of core/simd.hpp (as Eigen writes its algorithms
/// over packet functions): CoulombClassifyKernel and CoulombAllInsideKernel take one block of
/// P::width contacts per step, and only the schedule of blocks depends on the instruction set:
/// ScalarPack for float and the portable passes, PackD4 (whole blocks, the rest one by one)
/// with AVX2 + FMA, PackD8 from 8 contacts on with AVX-512F and VL. The SIMD passes are taken
/// for double unless GRIP_NO_SIMD is defined. They read each contact's normal and mu in place,
/// as one row of four (core/simd_rows.hpp transposes a block's rows into packs), and
/// deinterleave the stacked forces in registers.
/// The range check adds up the contacts' |x|^2 (size_bound) and falls back to the
/// component-by-component check only when a force comes near max_magnitude or holds a NaN.
/// Nothing depends on the CPU at run time: the choice is made by the compiler flags, so a binary
/// runs only where they allow. As with Eigen, compile every translation unit of one program with
/// the same SIMD flags.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "grip/contact/contact.hpp"
#include "grip/contact/contact_mode.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/simd.hpp"
#include "grip/core/simd_rows.hpp"

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

/// The cone rows of contacts stored one after another: contact i's normal a_i and friction
/// mu_i, (a_x, a_y, a_z, mu), are the four scalars at cone_rows(contacts) + i *
/// cone_row_stride<Scalar> (Contact keeps them as adjacent members; checked below).
template <class Scalar>
constexpr int cone_row_stride = static_cast<int>(sizeof(Contact<Scalar>) / sizeof(Scalar));
template <class Scalar>
const Scalar* cone_rows(const Contact<Scalar>* contacts) {
  return contacts->normal.data();
}
static_assert(std::is_standard_layout<Contact<double>>::value && std::is_standard_layout<Contact<float>>::value &&
                  offsetof(Contact<double>, friction) == offsetof(Contact<double>, normal) + 3 * sizeof(double) &&
                  offsetof(Contact<float>, friction) == offsetof(Contact<float>, normal) + 3 * sizeof(float) &&
                  sizeof(Contact<double>) % sizeof(double) == 0 && sizeof(Contact<float>) % sizeof(float) == 0,
              "the passes read a contact's normal and friction as one row of four scalars");

/// The Coulomb modes of contacts [0, n) with forces x (3n values, stacked), normals and mu read
/// from the cone rows at `cones` (row i, (a_x, a_y, a_z, mu_i), at cones + i * stride; only
/// the rows of [0, n) read), written to modes[0, n) (nothing else written; only the 3n values
/// of x read). Invalid forces are counted (the number of components NaN, Inf or beyond
/// max_magnitude), and their modes are unspecified. Through this translation unit's widest
/// pass for double: AVX-512 from 8 contacts on, else AVX2 (whole blocks of 4, the rest one by
/// one), else one by one; always one by one for float. FixedN: the grasp's compile-time
/// contact count (n == FixedN), or 0 (Dynamic).
template <int FixedN, class Scalar>
GRIP_ALWAYS_INLINE CoulombCounts classify_coulomb(const Scalar* cones, int stride, const Scalar* x, int n,
                                                  Scalar absolute_tolerance, Scalar relative_tolerance,
                                                  ContactMode* modes);

/// classify_coulomb one contact at a time (the reference the tests compare with).
template <class Scalar>
CoulombCounts classify_coulomb_portable(const Scalar* cones, int stride, const Scalar* x, int n,
                                        Scalar absolute_tolerance, Scalar relative_tolerance, ContactMode* modes);

/// True when every contact i in [0, n) pushes and lies inside or on its cone with no
/// tolerance: f_n = x_i.a_i > 0 and |x_i - f_n a_i|^2 <= (mu_i f_n)^2, i.e. CoulombCone's
/// `normal_part(x) > 0 && !slips(x, 0)` (solve_constrained's fast-path test). A NaN force
/// fails; no other check of the values (a finite force beyond max_magnitude may pass). The
/// lean form of classify_coulomb: no modes, counts or slack. Rows, FixedN and passes as
/// classify_coulomb (all blocks of 8 with AVX-512, the last one masked).
template <int FixedN, class Scalar>
bool coulomb_all_inside(const Scalar* cones, int stride, const Scalar* x, int n);

/// coulomb_all_inside one contact at a time.
template <class Scalar>
bool coulomb_all_inside_portable(const Scalar* cones, int stride, const Scalar* x, int n);

/// classify_coulomb over a whole hard-finger grasp (any Grasp type): the cone rows of its
/// contacts(), its size (compile-time when fixed) and its stacked forces x (grasp.unknowns()
/// values).
template <class GraspT, class Forces>
GRIP_ALWAYS_INLINE CoulombCounts classify_coulomb_grasp(const GraspT& grasp, const Forces& x,
                                                        typename GraspT::ScalarType absolute_tolerance,
                                                        typename GraspT::ScalarType relative_tolerance,
                                                        ContactMode* modes) {
  static_assert(GraspT::dim == 3, "the Coulomb pass is for hard fingers");
  using S = typename GraspT::ScalarType;
  return classify_coulomb<(GraspT::fixed_size > 0 ? GraspT::fixed_size : 0)>(
      cone_rows(grasp.contacts()), cone_row_stride<S>, x.data(), grasp.size(), absolute_tolerance, relative_tolerance,
      modes);
}

/// coulomb_all_inside over a whole hard-finger grasp and its stacked forces x.
template <class GraspT, class Forces>
bool coulomb_all_inside_grasp(const GraspT& grasp, const Forces& x) {
  static_assert(GraspT::dim == 3, "the Coulomb pass is for hard fingers");
  using S = typename GraspT::ScalarType;
  return coulomb_all_inside<(GraspT::fixed_size > 0 ? GraspT::fixed_size : 0)>(
      cone_rows(grasp.contacts()), cone_row_stride<S>, x.data(), grasp.size());
}

// ---------------------------------------------------------------------------------------------
// The kernels, generic over the pack P (core/simd.hpp).

static_assert(static_cast<int>(ContactMode::Sticking) == 0 && static_cast<int>(ContactMode::Sliding) == 1 &&
                  static_cast<int>(ContactMode::Separating) == 2 && sizeof(ContactMode) == 4,
              "the kernels store modes as 32-bit codes 0, 1, 2 (store_codes)");

/// Squared magnitudes summed per lane over the blocks of a pass, f_n^2 + |t|^2 for each
/// contact: the pass's cheap range check. f_n^2 + |t|^2 = |x|^2 + f_n^2 (|a|^2 - 1), and a
/// Contact's |a|^2 lies within 2 normal_tolerance of 1: so at most `size_bound` in every lane
/// proves every component within max_magnitude (a component is at most |x|; the bound leaves
/// room for |a| != 1 and the round-off of f_n, t and the sum). NaN or anything larger sends
/// the pass to forces_beyond_range(), the exact component-by-component check.
template <class S>
constexpr S size_bound =
    ScalarTraits<S>::max_magnitude* ScalarTraits<S>::max_magnitude*(S(1) - S(4) * ScalarTraits<S>::normal_tolerance);

/// The number of the 3n values of x that are NaN, Inf or beyond max_magnitude.
template <class Scalar>
int forces_beyond_range(const Scalar* x, int n) {
  int bad = 0;
  for (int i = 0; i < 3 * n; ++i) bad += int(!(std::abs(x[i]) <= ScalarTraits<Scalar>::max_magnitude));
  return bad;
}

/// The part of the rule both kernels share, for the block of contacts b .. b + width - 1 (or,
/// Masked, its first k) with forces fx, fy, fz: their cone rows loaded (lanes past k zero),
/// f_n = x.a written to `fn` and mu to `mu`, and |x - f_n a|^2 returned, with fused
/// multiply-adds where the pack has them.
template <bool Masked, class P, class S>
GRIP_ALWAYS_INLINE P coulomb_tangent_squared(const S* cones, int stride, int b, int k, P fx, P fy, P fz, P& fn, P& mu) {
  P nx, ny, nz;
  const S* rows = cones + std::ptrdiff_t(b) * stride;
  if constexpr (Masked)
    load_rows4(rows, stride, k, nx, ny, nz, mu);
  else
    load_rows4(rows, stride, nx, ny, nz, mu);
  fn = mul_add(fz, nz, mul_add(fy, ny, fx * nx));
  const P tx = neg_mul_add(fn, nx, fx), ty = neg_mul_add(fn, ny, fy), tz = neg_mul_add(fn, nz, fz);
  return mul_add(tz, tz, mul_add(ty, ty, tx * tx));
}

/// Loads the forces of one block: all P::width contacts, or (Masked) the first k of them.
template <bool Masked, class P, class S>
GRIP_ALWAYS_INLINE void load_block(const S* forces, int k, P& fx, P& fy, P& fz) {
  if constexpr (Masked)
    P::load_xyz(forces, k, fx, fy, fz);
  else
    P::load_xyz(forces, fx, fy, fz);
}

/// classify_coulomb's rule on one pack of contacts per step, with its counts and range sums.
/// NonNegativeSlack: both tolerances are >= 0, so that lim >= 0 wherever f_n > 0 (mu >= 0 is
/// a Contact invariant) and the test lim < 0 is dropped.
template <class P, bool NonNegativeSlack>
struct CoulombClassifyKernel {
  using Pack = P;
  using S = typename P::Scalar;
  const S* cones;
  int stride;
  ContactMode* modes;
  P tol_abs, tol_rel, zero, size;  // size: per lane, the sum of |x|^2 (see size_bound)
  CoulombCounts counts;

  CoulombClassifyKernel(const S* t, int s, ContactMode* m, S absolute_tolerance, S relative_tolerance)
      : cones(t),
        stride(s),
        modes(m),
        tol_abs(P::set1(absolute_tolerance)),
        tol_rel(P::set1(relative_tolerance)),
        zero(P::set1(S(0))),
        size(zero) {}

  /// Contacts b .. b + width - 1, forces from `forces` (= x + 3 b); Masked: only the first
  /// k (1 <= k; k >= width is a whole block) are read, written and counted.
  template <bool Masked>
  GRIP_ALWAYS_INLINE void step(int b, const S* forces, int k) {
    P fx, fy, fz, fn, mu;
    load_block<Masked>(forces, k, fx, fy, fz);
    const P t2 = coulomb_tangent_squared<Masked>(cones, stride, b, k, fx, fy, fz, fn, mu);
    size = size + mul_add(fn, fn, t2);
    // lim = (mu + relative_tolerance) f_n + absolute_tolerance; the slack is the last two terms.
    const P lim = mul_add(mu + tol_rel, fn, tol_abs);
    auto separating = not_greater(fn, zero);
    auto over = t2 > lim * lim;
    if constexpr (!NonNegativeSlack) over = over | (lim < zero);
    if constexpr (Masked) {
      const auto lanes = P::first(k);
      separating = separating & lanes;
      over = over & lanes;
    }
    const auto sliding = and_not(over, separating);
    if constexpr (Masked)
      P::store_codes(modes + b, k, sliding, separating);
    else
      P::store_codes(modes + b, sliding, separating);
    counts.separating += separating.count();
    counts.sliding += sliding.count();
  }

  /// True unless every lane's sum of |x|^2 is at most size_bound.
  bool beyond() const { return (size <= P::set1(size_bound<S>)).bits() != (1u << P::width) - 1u; }
};

/// coulomb_all_inside's rule on one pack of contacts per step.
template <class P>
struct CoulombAllInsideKernel {
  using Pack = P;
  using S = typename P::Scalar;
  const S* cones;
  int stride;
  P zero = P::set1(S(0));
  typename P::Mask inside = P::first(P::width);

  /// As CoulombClassifyKernel::step.
  template <bool Masked>
  GRIP_ALWAYS_INLINE void step(int b, const S* forces, int k) {
    P fx, fy, fz, fn, mu;
    load_block<Masked>(forces, k, fx, fy, fz);
    const P t2 = coulomb_tangent_squared<Masked>(cones, stride, b, k, fx, fy, fz, fn, mu);
    const P lim = mu * fn;
    const auto in = (fn > zero) & (t2 <= lim * lim);
    if constexpr (Masked)
      inside = inside & (in | !P::first(k));
    else
      inside = inside & in;
  }

  bool all() const { return inside.bits() == (1u << P::width) - 1u; }
};

/// Runs `kernel` over the `count` contacts from b (forces from `forces` = x + 3 b) in whole
/// blocks of its pack (count a multiple of the width).
template <class Kernel, class S>
GRIP_ALWAYS_INLINE void run_blocks(Kernel& kernel, int b, const S* forces, int count) {
  constexpr int w = Kernel::Pack::width;
  for (int i = 0; i < count; i += w) kernel.template step<false>(b + i, forces + 3 * i, count - i);
}

/// classify_coulomb's schedule for one sign of the slack (see the kernel), with SIMD packs or
/// (Simd false) one contact at a time; FixedN as classify_coulomb.
template <int FixedN, bool NonNegativeSlack, bool Simd, class S>
GRIP_ALWAYS_INLINE CoulombCounts classify_coulomb_pass(const S* cones, int stride, const S* x, int n_runtime,
                                                       S absolute_tolerance, S relative_tolerance, ContactMode* modes) {
  const int n = FixedN > 0 ? FixedN : n_runtime;
  using One = CoulombClassifyKernel<ScalarPack<S>, NonNegativeSlack>;
  CoulombCounts c;
  if constexpr (Simd && std::is_same<S, double>::value && (GRIP_SIMD_AVX512 || GRIP_SIMD_AVX2)) {
#if GRIP_SIMD_AVX512
    // Below one full block, 256-bit code is as fast, and it spares the core the wake-up of its
    // 512-bit units (measured: the first 512-bit pass after other code runs slower).
    if (n >= 8) {
      CoulombClassifyKernel<PackD8, NonNegativeSlack> k8(cones, stride, modes, absolute_tolerance, relative_tolerance);
      // A last block of 1 to 4 contacts takes 256-bit registers (below): half the work.
      const int blocks_end = n % 8 != 0 && n % 8 <= 4 ? n - n % 8 : n;
      int b = 0;
      for (; b + 8 <= blocks_end; b += 8) k8.template step<false>(b, x + 3 * b, 8);
      if (b < blocks_end) {
        k8.template step<true>(b, x + 3 * b, n - b);
        b += 8;
      }
      c = k8.counts;
      bool beyond = k8.beyond();
      if (b < n) {
        CoulombClassifyKernel<PackD4, NonNegativeSlack> k4(cones, stride, modes, absolute_tolerance,
                                                           relative_tolerance);
        k4.template step<true>(b, x + 3 * b, n - b);
        c.sliding += k4.counts.sliding;
        c.separating += k4.counts.separating;
        beyond = beyond || k4.beyond();
      }
      if (beyond) c.invalid = forces_beyond_range(x, n);
      return c;
    }
#endif
#if GRIP_SIMD_AVX2
    // Whole blocks of 4, then the rest one by one.
    CoulombClassifyKernel<PackD4, NonNegativeSlack> k4(cones, stride, modes, absolute_tolerance, relative_tolerance);
    const int b = n - n % 4;
    run_blocks(k4, 0, x, b);
    One k1(cones, stride, modes, absolute_tolerance, relative_tolerance);
    run_blocks(k1, b, x + 3 * b, n - b);
    c.sliding = k4.counts.sliding + k1.counts.sliding;
    c.separating = k4.counts.separating + k1.counts.separating;
    if (k4.beyond() || k1.beyond()) c.invalid = forces_beyond_range(x, n);
    return c;
#endif
  }
  One k1(cones, stride, modes, absolute_tolerance, relative_tolerance);
  run_blocks(k1, 0, x, n);
  c = k1.counts;
  if (k1.beyond()) c.invalid = forces_beyond_range(x, n);
  return c;
}

template <int FixedN, class Scalar>
GRIP_ALWAYS_INLINE CoulombCounts classify_coulomb(const Scalar* cones, int stride, const Scalar* x, int n,
                                                  Scalar absolute_tolerance, Scalar relative_tolerance,
                                                  ContactMode* modes) {
  if (absolute_tolerance >= 0 && relative_tolerance >= 0)
    return classify_coulomb_pass<FixedN, true, true>(cones, stride, x, n, absolute_tolerance, relative_tolerance,
                                                     modes);
  return classify_coulomb_pass<FixedN, false, true>(cones, stride, x, n, absolute_tolerance, relative_tolerance, modes);
}

template <class Scalar>
CoulombCounts classify_coulomb_portable(const Scalar* cones, int stride, const Scalar* x, int n,
                                        Scalar absolute_tolerance, Scalar relative_tolerance, ContactMode* modes) {
  if (absolute_tolerance >= 0 && relative_tolerance >= 0)
    return classify_coulomb_pass<0, true, false>(cones, stride, x, n, absolute_tolerance, relative_tolerance, modes);
  return classify_coulomb_pass<0, false, false>(cones, stride, x, n, absolute_tolerance, relative_tolerance, modes);
}

template <class Scalar>
bool coulomb_all_inside_portable(const Scalar* cones, int stride, const Scalar* x, int n) {
  CoulombAllInsideKernel<ScalarPack<Scalar>> k1{cones, stride};
  run_blocks(k1, 0, x, n);
  return k1.all();
}

template <int FixedN, class Scalar>
bool coulomb_all_inside(const Scalar* cones, int stride, const Scalar* x, int n_runtime) {
  const int n = FixedN > 0 ? FixedN : n_runtime;
  if constexpr (std::is_same<Scalar, double>::value && (GRIP_SIMD_AVX512 || GRIP_SIMD_AVX2)) {
#if GRIP_SIMD_AVX512
    // As in classify_coulomb: below one full block the 256-bit pass is as fast.
    if (n >= 8) {
      CoulombAllInsideKernel<PackD8> k8{cones, stride};
      for (int b = 0; b < n; b += 8) k8.template step<true>(b, x + 3 * b, n - b);
      return k8.all();
    }
#endif
#if GRIP_SIMD_AVX2
    CoulombAllInsideKernel<PackD4> k4{cones, stride};
    const int b = n - n % 4;
    run_blocks(k4, 0, x, b);
    return k4.all() && coulomb_all_inside_portable(cones + std::ptrdiff_t(b) * stride, stride, x + 3 * b, n - b);
#endif
  }
  return coulomb_all_inside_portable(cones, stride, x, n);
}

}  // namespace detail
}  // namespace grip
