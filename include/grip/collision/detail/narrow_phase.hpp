#pragma once
/// \file
/// The exact narrow phase of collision.hpp, for one phalanx in the object's frame: signed
/// distances of its samples from the object's own distance field, refinement along the axis
/// towards the capsule's deepest point, and the clustering of what penetrates into at most K
/// contacts.
///
/// Refinement. phi(t) = field distance at a + t (b - a). A sample j that is a local minimum
/// of the sampled phi (and within half a spacing of touching, see collision.hpp) starts a
/// search for the minimum over the half-interval towards which phi decreases, [t_{j-1}, t_j]
/// or [t_j, t_{j+1}], from phi and its slope phi'(t) = n(x(t)) . (b - a) at both ends
/// (refine()); the deepest point evaluated is kept. For a convex field phi(t) is convex, so
/// the minimiser of phi over [0, 1] lies within one spacing of the best sample and the search
/// brackets it: the phalanx's depth is its capsule's, r - min_t phi(t), within the search's
/// certified tolerance. Meshes (fields with a segment query) are refined by triangles instead
/// (refine_by_triangles()): each step minimises one triangle's distance over the bracket in
/// closed form, where slopes would creep along the mesh's kinks.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "grip/core/index.hpp"
#include "grip/core/types.hpp"
#include "grip/geometry/detail/field_probe.hpp"
#include "grip/collision/hand_contact.hpp"

namespace grip {
namespace detail {

/// A phalanx's axis in the object frame: points a + t (b - a), t in [0, 1], and its radius.
template <class Scalar>
struct PhalanxAxis {
  Vector3<Scalar> a{Vector3<Scalar>::Zero()};  ///< base
  Vector3<Scalar> b{Vector3<Scalar>::Zero()};  ///< tip
  Scalar radius{0};                            ///< capsule radius

  /// The axis point at t; exactly b at t = 1 (the next phalanx's base).
  Vector3<Scalar> at(Scalar t) const { return t == Scalar(1) ? b : Vector3<Scalar>(a + t * (b - a)); }
};

/// The last sample of a phalanx, which is the first of the next one of its digit (the tip of
/// one is the base of the next): its field value is evaluated once. x is NaN when there is none.
template <class Scalar>
struct JointSample {
  Vector3<Scalar> x{Vector3<Scalar>::Constant(std::numeric_limits<Scalar>::quiet_NaN())};
  Vector3<Scalar> normal{Vector3<Scalar>::UnitZ()};
  Scalar phi{0};      // the exact distance, when found
  Scalar limit{0};    // the band it was asked with
  int place{-1};      // the probe's place() after it
  bool found{false};  // phi known; else no surface within limit
};

/// The exact distances of a phalanx's samples (object frame), and which ones the broad
/// phase put in reach (those not in reach are farther than the band: never evaluated).
template <class Scalar, int Samples>
struct SampleField {
  std::array<Scalar, Samples> phi{};
  std::array<Vector3<Scalar>, Samples> normal{};
  std::array<bool, Samples> reach{};
  std::array<int, Samples> place{};  // the probe's place() after each evaluation (-1: none)
};

/// The band of a phalanx: a sample whose distance is below it may start a contact (its
/// radius, plus half a sample spacing when refining, see collision.hpp).
template <class Scalar, int Samples>
Scalar band_of(const PhalanxAxis<Scalar>& ax, const ContactSettings<Scalar>& settings) {
  const Scalar length = (ax.b - ax.a).norm();
  return ax.radius + (settings.refine_iterations > 0 ? Scalar(0.5) * length / Scalar(Samples - 1) : Scalar(0));
}

/// A place where the phalanx penetrates: a sample, or the deepest point a refinement found.
/// (Plain data, filled before use: the candidate arrays are not initialised.)
template <class Scalar>
struct Penetration {
  Scalar depth;            // r - phi
  Scalar t;                // axis parameter
  Scalar phi;              // signed distance of the axis point
  Vector3<Scalar> normal;  // outward
  int sample;              // the sample it comes from
  bool is_sample;          // a sample itself (counted in HandContact::samples)
};

/// Evaluates the field at the samples in reach; those with no surface within the band and
/// outside the object go out of reach, and so does a sample next to one at least a spacing
/// beyond the band (phi is 1-Lipschitz: it is beyond the band too). A centre x with no
/// surface within the band (a bounded field's miss) lies outside unless phi(x) <= -band;
/// phi(x) >= phi(previous sample) - spacing > -band proves it outside (a sample out of reach
/// or skipped lies beyond the band: phi >= band > spacing - band, as band > spacing / 2).
/// Otherwise `may_be_inside(x)` is asked: false when x surely lies outside the object (no
/// solid octree leaf holds it), true when the exact distance is needed.
template <class Scalar, int Samples, class Probe, class Inside>
void evaluate_samples(Probe& probe, const PhalanxAxis<Scalar>& ax, Scalar band, SampleField<Scalar, Samples>& s,
                      Inside&& may_be_inside, JointSample<Scalar>& joint) {
  const Scalar spacing = (ax.b - ax.a).norm() / Scalar(Samples - 1);
  const Scalar skip = band + spacing;
  bool far = false;                                         // the previous sample is at least a spacing beyond the band
  Scalar below = -std::numeric_limits<Scalar>::infinity();  // a lower bound of the previous phi
  for (int j = 0; j < Samples; ++j) {
    const auto sj = detail::idx(j);
    if (!s.reach[sj] || far) {
      s.reach[sj] = false;
      far = false;
      below = band;
      continue;
    }
    const Vector3<Scalar> x = ax.at(Scalar(j) / Scalar(Samples - 1));
    bool found = false;
    if (j == 0 && x == joint.x && (joint.found || !(joint.limit < band))) {  // the previous tip
      found = joint.found && (!Probe::bounded || std::abs(joint.phi) < band);
      s.phi[sj] = joint.phi;
      s.normal[sj] = joint.normal;
      probe.start_at(joint.place);
    } else {
      probe.start_at(-1);  // (the previous sample's triangle is a spacing away: a poor start)
      found = probe.within(x, band, s.phi[sj], s.normal[sj]);
    }
    if (found) {
      s.place[sj] = probe.place();
      far = s.phi[sj] >= skip;
      below = s.phi[sj];
    } else if (!(below - spacing > -band) && may_be_inside(x)) {  // deep inside, or in a solid leaf
      s.phi[sj] = probe.exact(x, s.normal[sj]);
      s.place[sj] = probe.place();
      far = s.phi[sj] >= skip;
      below = s.phi[sj];
      found = true;
    } else {
      s.reach[sj] = false;
      below = band;
    }
    if (j == Samples - 1) joint = JointSample<Scalar>{x, s.normal[sj], s.phi[sj], band, probe.place(), found};
  }
  if (!s.reach[Samples - 1]) joint = JointSample<Scalar>{};
}

/// Refinement by triangles (fields with a segment query: meshes), for sample j outside the
/// object (phi_j > 0). The distance to one triangle is convex along the axis, and its least
/// value over the axis points within a spacing of sample j is exact (segment_distance2()):
/// starting from sample j's nearest triangle, the field is evaluated at that least point, and
/// again from the triangle nearest there, until a point's nearest triangle is the one that
/// chose it, the value stops falling, the axis meets the triangle, or
/// `settings.refine_iterations` evaluations. Returns true only in the first case with the
/// point outside the object: the field touches that triangle's distance from below there, so
/// its slope along the axis is zero (or the point is a bracket end), which for a convex field
/// is the least value over the axis. `best` keeps the least value evaluated in every case.
template <class Scalar, int Samples, class Probe>
bool refine_by_triangles(Probe& probe, const PhalanxAxis<Scalar>& ax, const SampleField<Scalar, Samples>& s, int j,
                         Scalar band, const ContactSettings<Scalar>& settings, Penetration<Scalar>& best) {
  const Scalar h = Scalar(1) / Scalar(Samples - 1);
  const Scalar lo = std::max(Scalar(0), Scalar(j - 1) * h), hi = std::min(Scalar(1), Scalar(j + 1) * h);
  const Vector3<Scalar> p0 = ax.at(lo), p1 = ax.at(hi);
  const Scalar limit = band + (ax.b - ax.a).norm() * h;  // (every point within a spacing of sample j)
  int place = s.place[detail::idx(j)];
  Scalar last = best.phi;
  for (int it = 0; it < settings.refine_iterations && place >= 0; ++it) {
    Scalar u = Scalar(0);
    if (!(probe.field.segment_distance2(place, p0, p1, u) > Scalar(0))) return false;  // the axis meets it
    // At an end of the bracket: a sample, known already if it was evaluated.
    const int m = u == Scalar(0) ? std::max(0, j - 1) : (u == Scalar(1) ? std::min(Samples - 1, j + 1) : -1);
    Scalar t = lo + u * (hi - lo), phi = Scalar(0);
    Vector3<Scalar> n;
    int at = -1;
    if (m >= 0 && s.reach[detail::idx(m)]) {
      t = Scalar(m) / Scalar(Samples - 1);
      phi = s.phi[detail::idx(m)];
      n = s.normal[detail::idx(m)];
      at = s.place[detail::idx(m)];
    } else {
      probe.hint = place;
      if (!probe.within(ax.at(t), limit, phi, n)) phi = probe.exact(ax.at(t), n);
      at = probe.place();
    }
    if (phi < best.phi - settings.refine_tolerance) {  // (equally deep: the sample's is kept)
      best.phi = phi;
      best.t = t;
      best.normal = n;
    }
    if (at == place) return phi > Scalar(0);
    if (!(phi < last)) return false;
    last = phi;
    place = at;
  }
  return false;
}

/// The deepest point of the axis near sample j (see the file comment). The bracket runs from
/// t_j to the neighbouring sample towards which phi decreases; with phi and its slope
/// g = n . (b - a) known at both ends, the next point is the root of g's secant (exact where
/// phi is quadratic) and the intersection of the two end tangents (exact where phi is
/// piecewise linear, inside a box) in turn; the bracket end of the same slope sign moves
/// there. For convex phi the two tangents bound min phi from below: the iteration stops
/// when the best value is within `settings.refine_tolerance` of that bound, or after
/// `settings.refine_iterations` evaluations. A mesh is first refined by triangles; when that
/// search does not certify its point, this search follows (from the same samples, keeping the
/// least value found), with a budget of its own: at most 2 `refine_iterations` evaluations.
/// Either search replaces its best point only by one deeper by more than the tolerance: among
/// equally deep points (a phalanx lying along a face) the sample's is kept.
template <class Scalar, int Samples, class Probe>
Penetration<Scalar> refine(Probe& probe, const PhalanxAxis<Scalar>& ax, const SampleField<Scalar, Samples>& s, int j,
                           Scalar band, const ContactSettings<Scalar>& settings) {
  struct End {
    Scalar t, phi, slope;
  };
  const auto sj = detail::idx(j);
  const Scalar h = Scalar(1) / Scalar(Samples - 1);
  Penetration<Scalar> best{ax.radius - s.phi[sj], Scalar(j) * h, s.phi[sj], s.normal[sj], j, false};
  if constexpr (Probe::segments) {
    if (s.phi[sj] > Scalar(0) && refine_by_triangles(probe, ax, s, j, band, settings, best)) {
      best.depth = ax.radius - best.phi;
      return best;
    }
  }
  const Vector3<Scalar> d = ax.b - ax.a;
  const Scalar slope = s.normal[sj].dot(d);
  const int k = slope > Scalar(0) ? j - 1 : j + 1;
  int budget = settings.refine_iterations;
  best.depth = ax.radius - best.phi;
  if (slope == Scalar(0) || k < 0 || k >= Samples || budget <= 0) return best;
  // Every point of the bracket is within one spacing of sample j, below the band: its
  // distance is below band + spacing.
  const Scalar limit = band + d.norm() * h;
  auto distance = [&](Scalar t, Vector3<Scalar>& n) {
    Scalar phi = Scalar(0);
    if (!probe.within(ax.at(t), limit, phi, n)) phi = probe.exact(ax.at(t), n);
    return phi;
  };
  const auto sk = detail::idx(k);
  Vector3<Scalar> nk = s.normal[sk];
  Scalar phik = s.phi[sk];
  if (!s.reach[sk]) {  // farther than the band: not evaluated yet
    phik = distance(Scalar(k) * h, nk);
    --budget;
  }
  End lo{Scalar(j) * h, s.phi[sj], slope}, hi{Scalar(k) * h, phik, nk.dot(d)};
  if (k < j) std::swap(lo, hi);
  for (int it = 0; it < budget; ++it) {
    const Scalar dg = hi.slope - lo.slope;
    if (!(dg > Scalar(0))) break;  // no bracket of a minimum (not convex here)
    const Scalar t_tangents = (lo.phi - hi.phi + hi.slope * hi.t - lo.slope * lo.t) / dg;
    // The least over the bracket of the greater tangent: at their crossing if it lies inside,
    // else at an end (nearly parallel tangents: a phalanx lying along a face).
    auto tangents = [&](Scalar t) { return std::max(lo.phi + lo.slope * (t - lo.t), hi.phi + hi.slope * (t - hi.t)); };
    Scalar lower = std::min(tangents(lo.t), tangents(hi.t));
    if (t_tangents > lo.t && t_tangents < hi.t) lower = std::min(lower, tangents(t_tangents));
    if (!(best.phi - lower > settings.refine_tolerance)) break;
    Scalar t = it % 2 == 0 ? lo.t - lo.slope * (hi.t - lo.t) / dg : t_tangents;
    if (!(t > lo.t && t < hi.t)) t = Scalar(0.5) * (lo.t + hi.t);
    Vector3<Scalar> n;
    const Scalar phi = distance(t, n);
    if (phi < best.phi - settings.refine_tolerance) {  // (equally deep: the sample's is kept)
      best.phi = phi;
      best.t = t;
      best.normal = n;
    }
    const End e{t, phi, n.dot(d)};
    if (e.slope > Scalar(0))
      hi = e;
    else
      lo = e;
  }
  best.depth = ax.radius - best.phi;
  return best;
}

/// Sample j's penetration.
template <class Scalar>
Penetration<Scalar> sample_penetration(const PhalanxAxis<Scalar>& ax, int j, int samples, Scalar phi,
                                       const Vector3<Scalar>& normal) {
  return Penetration<Scalar>{ax.radius - phi, Scalar(j) / Scalar(samples - 1), phi, normal, j, true};
}

/// Sample j's penetrations of each part whose nearest point lies on the field's surface (not
/// buried in another part), appended to cand from index nc; returns the count after them.
template <int Parts, int Samples, class Scalar, class Field, std::size_t N>
int part_candidates(const Field& field, const PhalanxAxis<Scalar>& ax, int j, std::array<Penetration<Scalar>, N>& cand,
                    int nc) {
  constexpr int samples = Samples;
  const Vector3<Scalar> x = ax.at(Scalar(j) / Scalar(samples - 1));
  const int count = std::min(field.part_count(), Parts);
  const Scalar slack = Scalar(64) * std::numeric_limits<Scalar>::epsilon() * (x.norm() + ax.radius);
  for (int i = 0; i < count; ++i) {
    Vector3<Scalar> n;
    const Scalar phi = field.part_distance(i, x, n);
    if (!(phi < ax.radius)) continue;
    const Vector3<Scalar> q = x - phi * n;
    bool buried = false;
    for (int o = 0; o < count && !buried; ++o) {
      Vector3<Scalar> no;
      buried = o != i && field.part_distance(o, q, no) < -slack;
    }
    if (!buried) cand[detail::idx(nc++)] = sample_penetration(ax, j, samples, phi, n);
  }
  return nc;
}

/// The contacts of one phalanx (object frame), at most K, deepest first; returns their
/// number. Candidates: every refined local minimum of the sampled distance within `band` of
/// the axis (band = r + half a spacing when refining, r otherwise) that penetrates, and every
/// penetrating sample. They are taken deepest first: one within `cluster_angle` of a
/// contact's normal joins it (the nearest such), another starts one more contact while fewer
/// than K exist, else joins the contact of the nearest normal.
template <int K, class Scalar, int Samples, class Field, class Probe>
int phalanx_contacts(const Field& field, Probe& probe, const PhalanxAxis<Scalar>& ax,
                     const SampleField<Scalar, Samples>& s, Scalar band, const ContactSettings<Scalar>& settings,
                     std::array<Penetration<Scalar>, K>& out, std::array<int, K>& members) {
  constexpr int parts = K > 1 ? field_parts<Field>::max : 1;
  std::array<Penetration<Scalar>, (1 + parts) * Samples> cand;
  int nc = 0;
  // The local minima of the sampled distance within the band (the first of a run of equal
  // values), to refine. With K = 1 only the deepest contact is kept: they are refined by
  // increasing distance, and one whose bracket (points within a spacing of its sample, phi
  // 1-Lipschitz) cannot go below the best found so far is skipped.
  std::array<int, Samples> minima;
  int nm = 0;
  for (int j = 0; j < Samples; ++j) {
    const auto sj = detail::idx(j);
    if (!s.reach[sj]) continue;
    const Scalar phi = s.phi[sj];
    const bool left = j == 0 || !s.reach[sj - 1] || phi < s.phi[sj - 1];
    const bool right = j == Samples - 1 || !s.reach[sj + 1] || phi <= s.phi[sj + 1];
    if (left && right && phi < band) minima[detail::idx(nm++)] = j;
    if constexpr (parts > 1) {
      nc = part_candidates<parts, Samples>(field, ax, j, cand, nc);
    } else {
      if (phi < ax.radius) cand[detail::idx(nc++)] = sample_penetration(ax, j, Samples, phi, s.normal[sj]);
    }
  }
  if (K == 1)
    for (int i = 1; i < nm; ++i) {  // insertion sort by distance (at most Samples)
      const int j = minima[detail::idx(i)];
      int m = i;
      for (; m > 0 && s.phi[detail::idx(minima[detail::idx(m - 1)])] > s.phi[detail::idx(j)]; --m)
        minima[detail::idx(m)] = minima[detail::idx(m - 1)];
      minima[detail::idx(m)] = j;
    }
  const Scalar spacing = (ax.b - ax.a).norm() / Scalar(Samples - 1);
  Scalar deepest = ax.radius;  // the least distance refined so far (a contact needs less than r)
  for (int m = 0; m < nm; ++m) {
    const int j = minima[detail::idx(m)];
    if (K == 1 && !(s.phi[detail::idx(j)] - spacing < deepest)) continue;
    const Penetration<Scalar> p = refine(probe, ax, s, j, band, settings);
    if (p.depth > Scalar(0)) cand[detail::idx(nc++)] = p;
    deepest = std::min(deepest, p.phi);
  }
  // Deepest first (insertion sort: at most 2 Samples candidates); a refined point before the
  // sample it was refined from when both are equally deep.
  for (int i = 1; i < nc; ++i) {
    const Penetration<Scalar> p = cand[detail::idx(i)];
    int k = i;
    for (; k > 0; --k) {
      const Penetration<Scalar>& q = cand[detail::idx(k - 1)];
      if (q.depth > p.depth || (q.depth == p.depth && (!q.is_sample || p.is_sample))) break;
      cand[detail::idx(k)] = q;
    }
    cand[detail::idx(k)] = p;
  }
  const Scalar cos_join = K > 1 ? std::cos(settings.cluster_angle) : Scalar(1);
  int count = 0;
  for (int i = 0; i < nc; ++i) {
    const Penetration<Scalar>& p = cand[detail::idx(i)];
    int nearest = -1;
    Scalar best = Scalar(-2);
    for (int c = 0; c < count; ++c) {
      const Scalar dot = p.normal.dot(out[detail::idx(c)].normal);
      if (dot > best) {
        best = dot;
        nearest = c;
      }
    }
    if (nearest < 0 || (best < cos_join && count < K)) {
      out[detail::idx(count)] = p;
      members[detail::idx(count)] = p.is_sample ? 1 : 0;
      ++count;
    } else if (p.is_sample) {
      ++members[detail::idx(nearest)];
    }
  }
  return count;
}

}  // namespace detail
}  // namespace grip
