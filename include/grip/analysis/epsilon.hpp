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
///     w_ik = [d_ik ; (r_i x d_ik + m_ik a_i) / L]
/// with L the explicit lever length (m): moments are compared with forces as a force at
/// lever arm L (Ferrari-Canny's "lambda", Roa-Suarez's unit-conversion factor).
/// - L1 (sum of normal forces <= 1): W_1 = conv({0} U {w_ik});
/// - L-infinity (each normal force <= 1): W_inf = sum_i conv({0} U {w_ik : k}) (Minkowski).
/// epsilon = the radius of the largest ball about the origin inside W = min over unit u of
/// h_W(u), the support function: the smallest wrench (in the worst direction) the grasp can
/// resist per unit of force budget. epsilon > 0 iff the linearised grasp is in force closure.
///
/// Method (exact, like the expanding polytope algorithm of van den Bergen used for
/// penetration depth): keep an inner polytope Q of W (its vertices are support points of W),
/// its facets as 5-simplices with their adjacency (detail/epsilon_polytope.hpp). Take the
/// facet of Q nearest the origin (normal u, offset b); query the support point p of W along
/// u. If h_W(u) - b <= tolerance, then epsilon = b: b = dist(0, dQ) <= dist(0, dW) <= h_W(u)
/// (Q inside W). Otherwise p is a further vertex of W beyond that facet: add it (remove the
/// facets that see it, found by a breadth-first search over the adjacency from that facet,
/// and close the hole with the horizon). W has finitely many vertices, so this ends; it
/// touches only the facets near the origin, never the whole hull. Support of W_inf is the
/// sum of the per-contact supports, O(n K), so the exponentially large Minkowski sum is never
/// built.
/// All storage is in a caller-visible EpsilonWorkspace (no heap).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>

#include <Eigen/Geometry>

#include "grip/analysis/detail/epsilon_polytope.hpp"
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

/// Storage of the expanding-polytope search: at most MaxVertices support points (7 to 4096)
/// and MaxFacets facets. Default 10.6 MB for double (7.6 MB for float): keep one per thread
/// (static or heap in the caller), not in a small embedded stack. The default holds the
/// L-infinity search of 20 hard contacts with 8-sided pyramids (up to about 50 000 facets
/// and 550 vertices on random grasps). The ridge table holds the cone of up to
/// MaxFacets / 10 new facets of one added point (MaxFacets / 5 when MaxFacets is a power of
/// two); past any of these bounds the answer is IterationLimit.
template <class S, int MaxVertices = 1024, int MaxFacets = 65536>
struct EpsilonWorkspace {
  static_assert(MaxVertices >= 7 && MaxVertices <= detail::max_ridge_vertex + 1, "7 to 4096 vertices");
  static_assert(MaxFacets >= 7 && MaxFacets <= (1 << 27), "7 to 2^27 facets");
  static constexpr int max_vertices = MaxVertices;  ///< most support points kept
  static constexpr int max_facets = MaxFacets;      ///< most facets kept
  /// Most new facets of one added point (its horizon ridges): the ridge table's load bound.
  static constexpr int max_cone = MaxFacets / 5 + 1;
  /// Support points of W found so far: the vertices of the inner polytope Q.
  std::array<Wrench<S>, detail::idx(MaxVertices)> vertices;
  /// The facets of Q (the first Epsilon::facets of them in use at the end): sorted vertex
  /// indices.
  std::array<std::array<int, 6>, detail::idx(MaxFacets)> facet_vertices;
  /// The facets' planes: unit outward normal in [0, 6), offset in [6] (normal . x = offset on
  /// the facet: the origin's distance to it when the origin is inside), [7] a mark (-1 if
  /// removed, else the stamp of the last search that tested it): one 64-byte line per facet
  /// in double.
  alignas(64) std::array<std::array<S, 8>, detail::idx(MaxFacets)> planes;
  /// The facets' adjacency: neighbours[f][r] is the facet across the ridge of f without its
  /// vertex facet_vertices[f][r] (-1 if none), and has that ridge and points back.
  std::array<std::array<int, 6>, detail::idx(MaxFacets)> neighbours;
  /// Scratch of one step: the facets that see the added support point (the search's queue),
  /// then the slots of the new facets.
  std::array<int, detail::idx(MaxFacets)> visible;
  /// Scratch of one step: the horizon's ridges (five sorted vertex indices, packed by
  /// detail::ridge_key).
  std::array<std::uint64_t, detail::idx(max_cone)> horizon;
  /// Scratch of one step: the facet g across each horizon ridge and g's ridge s back, as
  /// 8 g + s (-1 if none).
  std::array<int, detail::idx(max_cone)> outside;
  /// Scratch of one step: how far the added point lies beyond each facet tested.
  std::array<S, detail::idx(MaxFacets)> margins;
  /// Scratch of one step: per horizon ridge, a candidate unit normal of the new facet through
  /// it (in the plane of the two facets' normals at the ridge; zero if there is none).
  std::array<Wrench<S>, detail::idx(max_cone)> cone_normals;
  /// Scratch of one step: the new facets whose candidate normal failed its check.
  std::array<int, detail::idx(max_cone)> rejects;
  /// Scratch of one step: a hash table of the new facets' ridges through the added point.
  std::array<detail::RidgeEntry, detail::idx(MaxFacets)> ridges;
  /// The facets' offsets again, contiguous and padded to a multiple of 8 (the nearest facet
  /// is found 8 offsets at a time).
  std::array<S, detail::idx((MaxFacets + 7) / 8 * 8)> offsets;
};

/// The outcome of ferrari_canny_epsilon().
///
/// Ok: epsilon exact to `tolerance * scale` (scale = largest primitive wrench norm).
/// IterationLimit: the workspace filled up; epsilon is then a lower bound (the nearest facet
/// of the inner polytope, or 0) and `upper` an upper bound. InvalidInput: incomplete grasp,
/// torque scale or tolerance not finite and > 0; zeros.
template <class Scalar>
struct Epsilon {
  Scalar epsilon{0};  ///< Ferrari-Canny epsilon (N per N of budget, moments / L); 0 if no closure.
  Scalar upper{0};    ///< The smallest support value h_W(u) found: epsilon <= upper.
  /// Unit wrench direction u (moment part scaled by 1/L) of the nearest facet: the
  /// weakest direction. When not in closure, every wrench of W has u . w <= ~0.
  Wrench<Scalar> direction{Wrench<Scalar>::Zero()};
  bool closure{false};                  ///< epsilon > tolerance * scale: linearised force closure.
  int vertices{0};                      ///< support points used.
  int facets{0};                        ///< facets of the final inner polytope.
  Status status{Status::InvalidInput};  ///< Ok, IterationLimit or InvalidInput (see above).
};

/// Ferrari-Canny epsilon of `grasp` with K-sided linearised cones, the given norm and
/// lever length L (m), using `ws` for storage. No heap. Cost: each step one support query
/// (O(n K)), work in proportion to the facets the added point sees and their neighbours
/// (detail/epsilon_polytope.hpp), and a pass over the facets' offsets for the nearest one.
template <int K, class GraspT, class Workspace>
Epsilon<typename GraspT::ScalarType> ferrari_canny_epsilon(
    const GraspT& grasp, EpsilonNorm norm, typename GraspT::ScalarType lever_length, Workspace& ws,
    typename GraspT::ScalarType tolerance = ScalarTraits<typename GraspT::ScalarType>::is_single_precision
                                                ? typename GraspT::ScalarType(1e-4)
                                                : typename GraspT::ScalarType(1e-10)) {
  static_assert(K >= 3, "a linearised cone needs K >= 3 sides");
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int P = detail::primitives_per_contact<M, K>();
  Epsilon<S> out;
  if (!grasp.complete() || !std::isfinite(lever_length) || !(lever_length > S(0)) || !std::isfinite(tolerance) ||
      !(tolerance > S(0)))
    return out;
  const int n = grasp.size();
  std::array<Wrench<S>, detail::idx(GraspT::capacity * P)> prim;
  S scale(0);
  for (int i = 0; i < n; ++i) {
    detail::contact_primitives<M, K>(grasp.contact(i), lever_length, &prim[detail::idx(i * P)]);
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

  detail::PolytopeFacets<S, Workspace> facets(ws, centre, std::numeric_limits<S>::epsilon() * scale);
  if (!facets.simplex()) return out;  // cannot happen: the simplex is full

  // 2. Expand towards the origin. `best` is the facet nearest the origin (least offset).
  out.status = Status::IterationLimit;
  int best = facets.nearest();
  while (true) {
    const Wrench<S> normal = facets.normal(best);
    const S h = support(normal, p);
    out.epsilon = std::max(S(0), facets.offset(best));
    if (h < out.upper) out.upper = h;
    out.direction = normal;
    if (h - facets.offset(best) <= tol) {
      out.status = Status::Ok;
      break;
    }
    if (nv >= Workspace::max_vertices) break;
    const int np = nv;  // the largest index: last in every new facet's sorted list
    ws.vertices[detail::idx(nv++)] = p;
    const int nvis = facets.find_visible(p, tol_visible, best);
    if (nvis < 0 || facets.count() - nvis + facets.horizon_size() > Workspace::max_facets) break;
    facets.replace_visible(np);
    best = facets.nearest();
    if (best < 0) break;  // no facet left (cannot happen: p lies outside a closed polytope)
  }
  out.vertices = nv;
  out.facets = facets.count();
  out.closure = out.epsilon > tol;
  if (!out.closure) out.epsilon = S(0);
  return out;
}

/// As above with a workspace of the default size from the heap (10.6 MB for double, one
/// allocation per call): an offline convenience. Repeated calls, and any thread that must not
/// allocate, pass a workspace kept in static storage or a member. Never throws: when the
/// allocation fails the answer is the one of a workspace full from the start, IterationLimit
/// with epsilon 0 (a lower bound) and upper the largest finite value.
template <int K, class GraspT>
Epsilon<typename GraspT::ScalarType> ferrari_canny_epsilon(const GraspT& grasp, EpsilonNorm norm,
                                                           typename GraspT::ScalarType lever_length) {
  using S = typename GraspT::ScalarType;
  const std::unique_ptr<EpsilonWorkspace<S>> ws(new (std::nothrow) EpsilonWorkspace<S>);
  if (ws == nullptr) {
    Epsilon<S> out;
    out.upper = std::numeric_limits<S>::max();
    out.status = Status::IterationLimit;
    return out;
  }
  return ferrari_canny_epsilon<K>(grasp, norm, lever_length, *ws);
}

}  // namespace grip
