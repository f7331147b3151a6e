#pragma once
/// \file
/// The inner polytope of ferrari_canny_epsilon() (analysis/epsilon.hpp): its facets in the
/// workspace's structure-of-arrays storage, and the steps of one expansion. Internal
/// (grip::detail), may change.
///
/// Facet f has sorted vertex indices facet_vertices[f], unit outward normal normals[.][f] and
/// offset offsets[f] (normal . x = offset on it). The planes are stored component by
/// component and padded to a multiple of 8 facets (padding: zero normal, largest offset), so
/// that the scan for the facets an added point sees runs 8 facets per operation and reads
/// 56 bytes per facet. One step, for an added support point p:
/// - scan(): the facets that see p (p beyond the plane by more than the visibility threshold)
///   and the nearest of the others;
/// - horizon(): the ridges (5 of a facet's 6 vertices) that exactly one visible facet has,
///   found with a hash table of the visible facets' ridge keys;
/// - remove_visible() then cone(): the visible facets go (each replaced by the list's last
///   one), and the facets joining p to the horizon come in, their normals computed 16 at a
///   time in SIMD lanes (facet_normals()).
/// Each step costs one pass over the planes plus O(V) for V visible facets.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "grip/analysis/detail/epsilon_normals.hpp"
#include "grip/core/index.hpp"
#include "grip/core/types.hpp"

namespace grip {
namespace detail {

/// The facets of the inner polytope, over the arrays of an EpsilonWorkspace `ws` (see the
/// file comment). `centre` is a point strictly inside the polytope; a new facet whose plane
/// passes within `flat` of it is degenerate and dropped.
template <class S, class Workspace>
class PolytopeFacets {
 public:
  PolytopeFacets(Workspace& ws, const Wrench<S>& centre, S flat) : ws_(ws), centre_(centre), flat_(flat) {}

  int count() const { return count_; }
  S offset(int f) const { return ws_.offsets[idx(f)]; }
  Wrench<S> normal(int f) const {
    Wrench<S> n;
    for (int i = 0; i < 6; ++i) n[i] = ws_.normals[idx(i)][idx(f)];
    return n;
  }

  /// The facets of the simplex of vertices 0 .. 6 (in general position). False if one is flat.
  bool simplex() {
    for (int skip = 0; skip < 7; ++skip)
      for (int k = 0, j = 0; k < 7; ++k)
        if (k != skip) ws_.facet_vertices[idx(skip)][idx(j++)] = k;
    return add(0, 7) == 7;
  }

  /// The facet with the least offset (nearest the origin when it is inside).
  int nearest() const {
    int best = 0;
    for (int f = 1; f < count_; ++f)
      if (offset(f) < offset(best)) best = f;
    return best;
  }

  /// The facets that see p (p . n - offset > threshold) into ws.visible[0 .. returned count),
  /// ascending, and in `best` the nearest of the others (-1 if none).
  int scan(const Wrench<S>& p, S threshold, int& best) const {
    using A = Eigen::Array<S, 8, 1>;
    using Map = Eigen::Map<const A>;
    int nvis = 0;
    best = -1;
    S best_offset = std::numeric_limits<S>::max();
    for (int f0 = 0; f0 < count_; f0 += 8) {
      const A off = Map(&ws_.offsets[idx(f0)]);
      A margin = -off;
      for (int i = 0; i < 6; ++i) margin += p[i] * Map(&ws_.normals[idx(i)][idx(f0)]);
      if (!(margin.maxCoeff() > threshold) && !(off.minCoeff() < best_offset)) continue;
      for (int l = 0; l < 8 && f0 + l < count_; ++l) {
        if (margin[l] > threshold) {
          ws_.visible[idx(nvis++)] = f0 + l;
        } else if (off[l] < best_offset) {
          best_offset = off[l];
          best = f0 + l;
        }
      }
    }
    return nvis;
  }

  /// The horizon of the nvis visible facets: its ridge keys into ws.ridges[0 .. returned
  /// count), or -1 if the scratch cannot hold the visible facets' ridges. The ridges go into
  /// an open-addressing hash table (linear probing, at most half full) in ws.ridges; a ridge
  /// met twice is marked shared (bit 63); the unshared ones are then moved to the front.
  int horizon(int nvis) const {
    const std::size_t nr = 6 * static_cast<std::size_t>(nvis);
    std::size_t slots = 16;
    int shift = 60;
    while (slots < 2 * nr) slots *= 2, --shift;
    if (slots > ws_.ridges.size()) return -1;
    constexpr std::uint64_t empty = ~std::uint64_t(0), shared = std::uint64_t(1) << 63;
    std::fill(ws_.ridges.begin(), ws_.ridges.begin() + static_cast<std::ptrdiff_t>(slots), empty);
    for (int a = 0; a < nvis; ++a) {
      const std::array<int, 6>& fv = ws_.facet_vertices[idx(ws_.visible[idx(a)])];
      for (int drop = 0; drop < 6; ++drop) {
        const std::uint64_t key = ridge_key(fv, drop);
        std::size_t h = static_cast<std::size_t>((key * 0x9e3779b97f4a7c15u) >> shift);
        while (ws_.ridges[h] != empty && (ws_.ridges[h] & ~shared) != key) h = (h + 1) & (slots - 1);
        ws_.ridges[h] = ws_.ridges[h] == empty ? key : (key | shared);
      }
    }
    int nh = 0;
    for (std::size_t h = 0; h < slots; ++h)
      if (ws_.ridges[h] != empty && (ws_.ridges[h] & shared) == 0) ws_.ridges[idx(nh++)] = ws_.ridges[h];
    return nh;
  }

  /// Removes the nvis visible facets, the last one first, each replaced by the list's last
  /// facet (never a visible one still to remove); `best` follows its facet.
  void remove_visible(int nvis, int& best) {
    for (int a = nvis - 1; a >= 0; --a) {
      const int f = ws_.visible[idx(a)];
      --count_;
      if (count_ == best) best = f;
      if (f != count_) move(count_, f);
    }
    pad();
  }

  /// Adds the facets joining vertex np (larger than every other index) to the nh horizon
  /// ridges; `best` becomes the nearest facet if a new one is nearer (or if it was -1).
  void cone(int np, int nh, int& best) {
    const int first = count_;
    for (int k = 0; k < nh; ++k) {
      std::array<int, 6>& v = ws_.facet_vertices[idx(first + k)];
      const std::array<int, 5> r = ridge_vertices(ws_.ridges[idx(k)]);
      for (int m = 0; m < 5; ++m) v[idx(m)] = r[idx(m)];
      v[5] = np;
    }
    add(first, nh);
    for (int f = first; f < count_; ++f)
      if (best < 0 || offset(f) < offset(best)) best = f;
  }

 private:
  // Facets [first, first + n) with their vertex lists set get their planes, oriented away
  // from the centre; flat ones are dropped. count_ becomes the end of those kept; returns
  // how many were kept.
  int add(int first, int n) {
    facet_normals<16>(ws_.vertices.data(), ws_.facet_vertices, first, n, ws_.normals);
    int end = first;
    for (int k = first; k < first + n; ++k) {
      const Wrench<S> nrm = normal(k);
      S off = nrm.dot(ws_.vertices[idx(ws_.facet_vertices[idx(k)][0])]);
      const S c = nrm.dot(centre_) - off;
      if (!(std::abs(c) > flat_)) continue;
      const S sign = c > S(0) ? S(-1) : S(1);
      ws_.offsets[idx(k)] = sign * off;
      for (int i = 0; i < 6; ++i) ws_.normals[idx(i)][idx(k)] *= sign;
      if (k != end) move(k, end);
      ++end;
    }
    count_ = end;
    pad();
    return end - first;
  }
  void move(int from, int to) {
    ws_.facet_vertices[idx(to)] = ws_.facet_vertices[idx(from)];
    ws_.offsets[idx(to)] = ws_.offsets[idx(from)];
    for (int i = 0; i < 6; ++i) ws_.normals[idx(i)][idx(to)] = ws_.normals[idx(i)][idx(from)];
  }
  // Lanes past the last facet, up to the next multiple of 8: seen by no point, never nearest.
  void pad() {
    for (int f = count_; f < (count_ + 7) / 8 * 8; ++f) {
      ws_.offsets[idx(f)] = std::numeric_limits<S>::max();
      for (int i = 0; i < 6; ++i) ws_.normals[idx(i)][idx(f)] = S(0);
    }
  }

  Workspace& ws_;
  Wrench<S> centre_;
  S flat_;
  int count_{0};
};

}  // namespace detail
}  // namespace grip
