#pragma once
/// \file
/// What the interior-point method's passes (conic_lanes.hpp) hand to its driver
/// (interior_point.hpp), namespace grip::detail: the sums over the contacts of one pass, from
/// which the driver forms and solves its 6 x 6 systems and the embedding's tau row.

#include "grip/core/types.hpp"

namespace grip {
namespace detail {

/// The sums of ConicLanes::assemble, at the iterate (u, z, s, t, y, tau). gq_i and gp_i are the
/// right-hand sides of the constant system and of the predictor (see ConicLanes).
template <class S>
struct AssembleSums {
  Matrix6<S> schur;  ///< S = sum A_i B_i^-1 A_i^T (symmetric)
  Wrench<S> au;      ///< sum A_i u_i
  Wrench<S> a_bq;    ///< sum A_i B_i^-1 gq_i
  Wrench<S> a_bp;    ///< sum A_i B_i^-1 gp_i
  S kp{0};           ///< sum -c_i (t_i / s_i)(rb_i - s_i): the predictor's bound term of the tau row
  Wrench<S> h;       ///< sum A_i B_i^-1 c_i, c_i = q_i + 2 P_i u_i / tau + e c_i t_i / s_i (the tau row)
  S c_bq{0};         ///< sum c_i^T B_i^-1 gq_i
  S c_bp{0};         ///< sum c_i^T B_i^-1 gp_i
  S cc_hb{0};        ///< sum c_i^2 t_i / s_i (bound rows)
  S upu{0};          ///< sum u_i^T P_i u_i
  S qu{0};           ///< sum q_i^T u_i
  S ct{0};           ///< sum c_i t_i (b^T z over the bound rows)
  S gap{0};          ///< sum u_i^T z_i + s_i t_i
  S rx2{0};          ///< |rx|^2, rx_i = P_i u_i + A_i^T y - z_i + q_i tau + e t_i
  S rb2{0};          ///< |rb|^2, rb_i = u_i0 + s_i - c_i tau (bound rows)
  S x2{0};           ///< sum |M_i u_i|^2 (ConicLanes::set's metric): the forces' squared norm
  S z2{0};           ///< sum |z_i|^2 + t_i^2
  S certificate{0};  ///< min_i margin(A_i^T y + e t_i): a primal infeasibility certificate needs >= 0
  bool ok{true};     ///< every scaling valid (both variables interior, finite)
};

/// The sums of ConicLanes::predict. The corrector's right-hand side is g0 + sigma g1 + sigma mu g2
/// + max(gamma - sigma, 0) mu g3 (g3: ConeBlock::recentre_part).
template <class S>
struct PredictSums {
  Wrench<S> a_bg[4];  ///< sum A_i B_i^-1 g_k,i (k = 0, 1, 2, 3)
  S c_bg[4]{};        ///< sum c_i^T B_i^-1 g_k,i
  S k[3]{};           ///< the corrector's bound terms of the tau row, parts 0, 1, 2
  S step{0};          ///< the largest step in [0, inf) keeping u, z, s, t in their cones
  S gap1{0};          ///< sum u^T dz + du^T z + s dt + ds t
  S gap2{0};          ///< sum du^T dz + ds dt
  /// sum |W^-1 u2|^2 + (u2 - u / tau)^T P (u2 - u / tau) + (t / s)(u2_0 - c)^2: minus the tau
  /// row's denominator less kappa / tau, as a sum of squares (the linear form from assemble's
  /// sums cancels, which float cannot afford near the optimum).
  S den{0};
};
}  // namespace detail
}  // namespace grip
