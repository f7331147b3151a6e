#pragma once
/// \file
/// The Ferrari-Canny epsilon quality (L1 and L-infinity), exactly, for linearised cones,
/// without a convex-hull library: an expanding-polytope search that only needs the
/// support function of the grasp wrench set.
///
/// Definitions (Ferrari & Canny, "Planning optimal grasps", ICRA 1992; Roa & Suarez 2015
/// section 4.3 "Q_LRW"). Each contact's exact cone is replaced by K primitive forces of unit
/// normal component on its surface (the inscribed pyramid): d_ik = a_i + mu_i (cos th_k t1 +
/// sin th_k t2), th_k = 2 pi k / K, with (t1, t2) the tangent basis of detail::tangent_basis(). A
/// soft finger adds the two torsion primitives (a_i, +-mu_t,i); a frictionless point has
/// the single primitive a_i. The primitive wrenches are
///     w_ik = [d_ik ; (r_i x d_ik + m_ik a_i) / rho]
/// with rho the explicit torque scale (m): moments are compared with forces as a force at
/// lever arm rho (Ferrari-Canny's "lambda", Roa-Suarez's unit-conversion factor).
/// - L1 (sum of normal forces <= 1): W_1 = conv({0} U {w_ik});
/// - L-infinity (each normal force <= 1): W_inf = sum_i conv({0} U {w_ik : k}) (Minkowski).
/// epsilon = the radius of the largest ball about the origin inside W = min over unit u of
/// h_W(u), the support function: the smallest wrench (in the worst direction) the grasp can
/// resist per unit of force budget. epsilon > 0 iff the linearised grasp is in force closure.
///
/// Method (exact, like the expanding polytope algorithm of van den Bergen used for
/// penetration depth): keep an inner polytope Q of W (its vertices are support points of W),
/// its facets as a flat list of 5-simplices. Take the facet of Q nearest the origin
/// (normal u, offset b); query the support point p of W along u. If h_W(u) - b <= tolerance,
/// then epsilon = b: b = dist(0, dQ) <= dist(0, dW) <= h_W(u) (Q inside W). Otherwise p
/// is a further vertex of W beyond that facet: add it (remove the facets that see it, close
/// the hole with the horizon). W has finitely many vertices, so this ends; it touches only
/// the facets near the origin, never the whole hull. Support of W_inf is the sum of the
/// per-contact supports, O(n K), so the exponentially large Minkowski sum is never built.
/// All storage is in a caller-visible EpsilonWorkspace (no heap).

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>

#include <Eigen/Geometry>
#include <Eigen/QR>

#include "grip/analysis/detail/epsilon_primitives.hpp"
#include "grip/contact/contact_model.hpp"
#include "grip/core/index.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"

namespace grip {

/// Which force budget epsilon is measured with.
enum class EpsilonNorm {
  L1,         ///< sum of normal forces <= 1: W = conv(all primitive wrenches, 0).
  LInfinity,  ///< every normal force <= 1: W = Minkowski sum of per-contact hulls.
};

/// Storage of the expanding-polytope search: at most MaxVertices support points and
/// MaxFacets facets. Default ~2.0 MB (1.9 MiB) for double: keep one per thread (static or heap in
/// the caller), not in a small embedded stack.
template <class S, int MaxVertices = 512, int MaxFacets = 16384>
struct EpsilonWorkspace {
  static constexpr int max_vertices = MaxVertices;  ///< most support points kept
  static constexpr int max_facets = MaxFacets;      ///< most facets kept (and horizon ridges per step)
  /// One facet: six vertex indices (sorted), unit outward normal, offset (normal . x = offset).
  struct Facet {
    std::array<int, 6> v;  ///< indices into `vertices`, ascending
    Wrench<S> normal;      ///< unit normal, pointing away from the polytope's centre
    S offset;              ///< normal . x on the facet: the origin's distance to it when the origin is inside
  };
  /// Support points of W found so far: the vertices of the inner polytope Q.
  std::array<Wrench<S>, detail::idx(MaxVertices)> vertices;
  /// The facets of Q, a compact list (Epsilon::facets of them in use at the end).
  std::array<Facet, detail::idx(MaxFacets)> facets;
  /// Scratch of one step: indices of the facets that see the added support point.
  std::array<int, detail::idx(MaxFacets)> visible;
  /// Scratch of one step: the horizon ridges (five sorted vertex indices) that close the hole.
  std::array<std::array<int, 5>, detail::idx(MaxFacets)> horizon;
  /// Scratch of one step: per facet, whether it sees the added support point.
  std::array<bool, detail::idx(MaxFacets)> is_visible;
};

/// The outcome of ferrari_canny_epsilon().
///
/// Ok: epsilon exact to `tolerance * scale` (scale = largest primitive wrench norm).
/// IterationLimit: the workspace filled up; epsilon is then a lower bound (the nearest facet
/// of the inner polytope, or 0) and `upper` an upper bound. InvalidInput: incomplete grasp,
/// torque scale or tolerance not finite and > 0; zeros.
template <class Scalar>
struct Epsilon {
  Scalar epsilon{0};  ///< Ferrari-Canny epsilon (N per N of budget, moments / rho); 0 if no closure.
  Scalar upper{0};    ///< The smallest support value h_W(u) found: epsilon <= upper.
  /// Unit wrench direction u (moment part scaled by 1/rho) of the nearest facet: the
  /// weakest direction. When not in closure, every wrench of W has u . w <= ~0.
  Wrench<Scalar> direction{Wrench<Scalar>::Zero()};
  bool closure{false};  ///< epsilon > tolerance * scale: linearised force closure.
  int vertices{0};      ///< support points used.
  int facets{0};        ///< facets of the final inner polytope.
  Status status{Status::InvalidInput};  ///< Ok, IterationLimit or InvalidInput (see above).
};

/// Ferrari-Canny epsilon of `grasp` with K-sided linearised cones, the given norm and
/// torque scale rho (m), using `ws` for storage. No heap. Cost: each step one support query
/// (O(n K)) and one pass over the current facets.
template <int K, class GraspT, class Workspace>
Epsilon<typename GraspT::ScalarType> ferrari_canny_epsilon(const GraspT& grasp, EpsilonNorm norm,
                                                           typename GraspT::ScalarType torque_scale, Workspace& ws,
                                                           typename GraspT::ScalarType tolerance =
                                                               ScalarTraits<typename GraspT::ScalarType>::is_single_precision
                                                                   ? typename GraspT::ScalarType(1e-4)
                                                                   : typename GraspT::ScalarType(1e-10)) {
  static_assert(K >= 3, "a linearised cone needs K >= 3 sides");
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  using Facet = typename Workspace::Facet;
  constexpr int P = detail::primitives_per_contact<M, K>();
  Epsilon<S> out;
  if (!grasp.complete() || !std::isfinite(torque_scale) || !(torque_scale > S(0)) || !std::isfinite(tolerance) ||
      !(tolerance > S(0)))
    return out;
  const int n = grasp.size();
  std::array<Wrench<S>, detail::idx(GraspT::capacity * P)> prim;
  S scale(0);
  for (int i = 0; i < n; ++i) {
    detail::contact_primitives<M, K>(grasp.contact(i), torque_scale, &prim[detail::idx(i * P)]);
    for (int k = 0; k < P; ++k) scale = std::max(scale, prim[detail::idx(i * P + k)].norm());
  }
  if (!std::isfinite(scale)) return out;
  out.status = Status::Ok;
  if (n == 0 || scale == S(0)) return out;
  const S tol = tolerance * scale;
  // Visibility threshold: above round-off in a facet test (~ 64 eps scale), below tol.
  const S tol_visible = std::max(S(1e-3) * tol, S(64) * std::numeric_limits<S>::epsilon() * scale);

  // Support point of W along u (and its value).
  auto support = [&](const Wrench<S>& u, Wrench<S>& p) {
    p.setZero();
    S h(0);
    if (norm == EpsilonNorm::L1) {
      for (int j = 0; j < n * P; ++j) {
        const S v = u.dot(prim[detail::idx(j)]);
        if (v > h) {
          h = v;
          p = prim[detail::idx(j)];
        }
      }
    } else {
      for (int i = 0; i < n; ++i) {
        S best(0);
        int arg = -1;
        for (int k = 0; k < P; ++k) {
          const S v = u.dot(prim[detail::idx(i * P + k)]);
          if (v > best) {
            best = v;
            arg = i * P + k;
          }
        }
        if (arg >= 0) {
          h += best;
          p += prim[detail::idx(arg)];
        }
      }
    }
    return h;
  };

  // 1. An initial 6-simplex of support points (or W is flat: epsilon = 0).
  int nv = 0;
  std::array<Wrench<S>, 6> basis;
  Wrench<S> p;
  support(Wrench<S>::UnitX(), p);
  ws.vertices[0] = p;
  nv = 1;
  out.upper = std::numeric_limits<S>::max();
  for (int k = 0; k < 6; ++k) {
    // A direction orthogonal to the span so far: the coordinate axis with the largest residual.
    Wrench<S> d = Wrench<S>::Zero();
    S dn(-1);
    for (int e = 0; e < 6; ++e) {
      Wrench<S> r = Wrench<S>::Unit(e);
      for (int b = 0; b < k; ++b) r -= basis[detail::idx(b)].dot(r) * basis[detail::idx(b)];
      if (r.norm() > dn) {
        dn = r.norm();
        d = r;
      }
    }
    d /= dn;
    Wrench<S> best_res = Wrench<S>::Zero(), best_p = Wrench<S>::Zero();
    for (int sgn = 0; sgn < 2; ++sgn) {
      const Wrench<S> u = sgn == 0 ? d : Wrench<S>(-d);
      Wrench<S> q;
      const S h = support(u, q);
      if (h < out.upper) {
        out.upper = h;
        out.direction = u;
      }
      Wrench<S> r = q - ws.vertices[0];
      for (int b = 0; b < k; ++b) r -= basis[detail::idx(b)].dot(r) * basis[detail::idx(b)];
      if (r.norm() > best_res.norm()) {
        best_res = r;
        best_p = q;
      }
    }
    if (!(best_res.norm() > tol)) {
      // W lies in the hyperplane d . w = d . v0 (= 0 since 0 is in W): no closure.
      out.epsilon = S(0);
      out.upper = S(0);
      const S side = d.dot(ws.vertices[0]);
      out.direction = side <= S(0) ? d : Wrench<S>(-d);
      out.vertices = nv;
      return out;
    }
    basis[detail::idx(k)] = best_res / best_res.norm();
    ws.vertices[detail::idx(nv++)] = best_p;
  }
  Wrench<S> centre = Wrench<S>::Zero();
  for (int k = 0; k < 7; ++k) centre += ws.vertices[detail::idx(k)];
  centre /= S(7);

  // Plane through six vertices, oriented away from the centre. False if degenerate.
  auto make_facet = [&](const std::array<int, 6>& v, Facet& f) {
    Eigen::Matrix<S, 6, 5> e;
    for (int k = 1; k < 6; ++k)
      e.col(k - 1) = ws.vertices[detail::idx(v[detail::idx(k)])] -
                     ws.vertices[detail::idx(v[0])];
    Eigen::HouseholderQR<Eigen::Matrix<S, 6, 5>> qr(e);
    Wrench<S> nrm = qr.householderQ() * Wrench<S>::Unit(5);
    S off = nrm.dot(ws.vertices[detail::idx(v[0])]);
    const S c = nrm.dot(centre) - off;
    if (!(std::abs(c) > std::numeric_limits<S>::epsilon() * scale)) return false;
    if (c > S(0)) {
      nrm = -nrm;
      off = -off;
    }
    f.v = v;
    f.normal = nrm;
    f.offset = off;
    return true;
  };
  int nf = 0;
  for (int skip = 0; skip < 7; ++skip) {
    std::array<int, 6> v{};
    for (int k = 0, j = 0; k < 7; ++k)
      if (k != skip) v[detail::idx(j++)] = k;
    if (!make_facet(v, ws.facets[detail::idx(nf)])) return out;  // cannot happen: simplex is full
    ++nf;
  }

  // 2. Expand towards the origin.
  out.status = Status::IterationLimit;
  while (true) {
    int best = 0;
    for (int f = 1; f < nf; ++f)
      if (ws.facets[detail::idx(f)].offset < ws.facets[detail::idx(best)].offset) best = f;
    const Facet& fb = ws.facets[detail::idx(best)];
    const S h = support(fb.normal, p);
    out.epsilon = std::max(S(0), fb.offset);
    if (h < out.upper) {
      out.upper = h;
    }
    out.direction = fb.normal;
    if (h - fb.offset <= tol) {
      out.status = Status::Ok;
      break;
    }
    if (nv >= Workspace::max_vertices) break;
    const int np = nv;
    ws.vertices[detail::idx(nv++)] = p;
    // Facets that see p.
    int nvis = 0;
    for (int f = 0; f < nf; ++f) {
      const Facet& ff = ws.facets[detail::idx(f)];
      const bool vis = ff.normal.dot(p) - ff.offset > tol_visible;
      ws.is_visible[detail::idx(f)] = vis;
      if (vis) ws.visible[detail::idx(nvis++)] = f;
    }
    // Horizon: ridges of visible facets not shared with another visible facet.
    int nh = 0;
    bool full = false;
    for (int a = 0; a < nvis && !full; ++a) {
      const Facet& fa = ws.facets[detail::idx(ws.visible[detail::idx(a)])];
      for (int drop = 0; drop < 6; ++drop) {
        std::array<int, 5> r{};
        for (int k = 0, j = 0; k < 6; ++k)
          if (k != drop) r[detail::idx(j++)] = fa.v[detail::idx(k)];
        bool shared = false;
        for (int b = 0; b < nvis && !shared; ++b)
          if (b != a && detail::ridge_in_facet(r, ws.facets[detail::idx(ws.visible[detail::idx(b)])].v))
            shared = true;
        if (!shared) {
          if (nh >= Workspace::max_facets) {
            full = true;
            break;
          }
          ws.horizon[detail::idx(nh++)] = r;
        }
      }
    }
    if (full || nf - nvis + nh > Workspace::max_facets) break;
    // Remove the visible facets (compact the list), then add the cone from p to the horizon.
    int w = 0;
    for (int f = 0; f < nf; ++f)
      if (!ws.is_visible[detail::idx(f)]) ws.facets[detail::idx(w++)] = ws.facets[detail::idx(f)];
    nf = w;
    for (int k = 0; k < nh; ++k) {
      std::array<int, 6> v{};
      const std::array<int, 5>& r = ws.horizon[detail::idx(k)];
      int j = 0;
      bool placed = false;
      for (int m = 0; m < 5; ++m) {
        if (!placed && np < r[detail::idx(m)]) {
          v[detail::idx(j++)] = np;
          placed = true;
        }
        v[detail::idx(j++)] = r[detail::idx(m)];
      }
      if (!placed) v[5] = np;
      if (make_facet(v, ws.facets[detail::idx(nf)])) ++nf;
    }
  }
  out.vertices = nv;
  out.facets = nf;
  out.closure = out.epsilon > tol;
  if (!out.closure) out.epsilon = S(0);
  return out;
}

/// As above with a workspace of the default size from the heap (about 2.0 MB for double, one
/// allocation per call): an offline convenience. Repeated calls, and any thread that must not
/// allocate, pass a workspace kept in static storage or a member. Never throws: when the
/// allocation fails the answer is the one of a workspace full from the start, IterationLimit
/// with epsilon 0 (a lower bound) and upper the largest finite value.
template <int K, class GraspT>
Epsilon<typename GraspT::ScalarType> ferrari_canny_epsilon(const GraspT& grasp, EpsilonNorm norm,
                                                           typename GraspT::ScalarType torque_scale) {
  using S = typename GraspT::ScalarType;
  const std::unique_ptr<EpsilonWorkspace<S>> ws(new (std::nothrow) EpsilonWorkspace<S>);
  if (ws == nullptr) {
    Epsilon<S> out;
    out.upper = std::numeric_limits<S>::max();
    out.status = Status::IterationLimit;
    return out;
  }
  return ferrari_canny_epsilon<K>(grasp, norm, torque_scale, *ws);
}

}  // namespace grip
