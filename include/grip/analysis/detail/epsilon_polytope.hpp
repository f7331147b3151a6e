#pragma once
/// \file
/// The inner polytope of ferrari_canny_epsilon() (analysis/epsilon.hpp): its facets and
/// their adjacency in the workspace, and the steps of one expansion. Internal (grip::detail),
/// may change.
///
/// Facet f has sorted vertex indices facet_vertices[f], its plane planes[f] (unit outward
/// normal in [0, 6), offset in [6]: normal . x = offset on it; [7] its mark) and
/// neighbours[f][r], the facet across its ridge r (its vertices without
/// facet_vertices[f][r]; -1 if none), which has that ridge and points back. The live facets
/// are 0 .. count() - 1. One step, for an added support point p beyond the facet `best`
/// nearest the origin:
/// - find_visible(): a breadth-first search over the adjacency from `best` collects the
///   facets that see p (p beyond the plane by more than the visibility threshold: the visible
///   region of a convex polytope is connected) and the horizon, the ridges between a visible
///   facet and one that is not. Its cost is the visible facets and their neighbours, not the
///   polytope; the set is connected and holds `best` by construction, even where round-off
///   makes a test near the threshold go either way, so the horizon is closed;
/// - replace_visible(): the facets joining p to the horizon take the visible facets' slots
///   (then the end of the list). The normal of each is first taken in the plane of the two
///   normals at its horizon ridge (m_f n_g - m_g n_f, with m the margins of p over the visible
///   facet f and the one across, g) and kept if it is normal to each of the facet's edges
///   within 4 u of the edge's length (u the unit round-off); the others (a few in a hundred)
///   are computed from the vertices, 16 at a time in SIMD lanes (facet_normals()). Each new
///   facet is linked to the facet across its horizon ridge and, through a hash table of ridge
///   keys, to the new facets beside it; slots left over are filled from the end of the list;
/// - nearest(): the least offset, from a pass over the contiguous offsets, 8 at a time.

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

/// One slot of the ridge table of replace_visible(): a ridge key and the facet and ridge
/// (8 f + r) waiting for its partner (-1 once matched).
struct RidgeEntry {
  std::uint64_t key;  ///< detail::ridge_key() of the ridge, all ones if the slot is empty
  int owner;          ///< 8 f + r, or -1
};

/// The facets of the inner polytope, over the arrays of an EpsilonWorkspace `ws` (see the
/// file comment). `centre` is a point strictly inside the polytope; a new facet whose plane
/// passes within `flat` of it is degenerate and dropped.
template <class S, class Workspace>
class PolytopeFacets {
 public:
  PolytopeFacets(Workspace& ws, const Wrench<S>& centre, S flat) : ws_(ws), centre_(centre), flat_(flat) {}

  /// Live facets: 0 .. count() - 1.
  int count() const { return count_; }
  /// The offset of facet f (normal . x on its plane).
  S offset(int f) const { return ws_.planes[idx(f)][6]; }
  /// The unit outward normal of facet f.
  Wrench<S> normal(int f) const {
    Wrench<S> n;
    for (int i = 0; i < 6; ++i) n[i] = ws_.planes[idx(f)][idx(i)];
    return n;
  }
  /// How far p lies beyond the plane of facet f (positive outside).
  S margin(int f, const Wrench<S>& p) const {
    const std::array<S, 8>& pl = ws_.planes[idx(f)];
    S m = -pl[6];
    for (int i = 0; i < 6; ++i) m += p[i] * pl[idx(i)];
    return m;
  }
  /// Horizon ridges of the last find_visible().
  int horizon_size() const { return nh_; }

  /// The facets of the simplex of vertices 0 .. 6 (in general position), with their
  /// adjacency and offsets. False if one is flat.
  bool simplex() {
    stamp_ = 0;
    for (int skip = 0; skip < 7; ++skip) {
      for (int k = 0, j = 0; k < 7; ++k)
        if (k != skip) ws_.facet_vertices[idx(skip)][idx(j++)] = k;
      // Across the ridge without vertex v lies the facet without v: facet v.
      ws_.neighbours[idx(skip)] = ws_.facet_vertices[idx(skip)];
      ws_.visible[idx(skip)] = skip;
    }
    count_ = 7;
    if (planes(7, false) != 0) return false;
    pad();
    return true;
  }

  /// The live facet with the least offset (the first of ties), -1 if none: a pass over the
  /// offsets, 8 at a time.
  int nearest() const {
    using A = Eigen::Array<S, 8, 1>;
    int best = -1;
    S best_offset = std::numeric_limits<S>::max();
    for (int f0 = 0; f0 < count_; f0 += 8) {
      const A off = Eigen::Map<const A>(&ws_.offsets[idx(f0)]);
      if (!(off.minCoeff() < best_offset)) continue;
      for (int l = 0; l < 8 && f0 + l < count_; ++l)
        if (off[l] < best_offset) best_offset = off[l], best = f0 + l;
    }
    return best;
  }

  /// The facets that see p (margin() > threshold), searched breadth first from `best` (taken
  /// as seeing p), into ws.visible[0 .. returned count); the horizon into ws.horizon (ridge
  /// keys), ws.outside (8 g + s for the facet g across and its ridge s back, -1 where there
  /// is none) and ws.cone_normals (a candidate normal of the new facet), horizon_size() of
  /// them. Returns -1, the polytope unchanged, if the scratch cannot hold the horizon or the
  /// new facets' ridge table.
  int find_visible(const Wrench<S>& p, S threshold, int best) {
    stamp_ += 2;
    const int seen = stamp_, sees = stamp_ + 1;  // marks of this search: tested, and seeing p
    int nvis = 0;
    nh_ = 0;
    mark(best) = S(sees);
    ws_.margins[idx(best)] = margin(best, p);
    ws_.visible[idx(nvis++)] = best;
    for (int a = 0; a < nvis; ++a) {
      const int f = ws_.visible[idx(a)];
      for (int r = 0; r < 6; ++r) {
        const int g = ws_.neighbours[idx(f)][idx(r)];
        if (g >= 0) {
          S& m = mark(g);
          if (m == S(sees)) continue;
          if (m != S(seen)) {
            const S mg = margin(g, p);
            ws_.margins[idx(g)] = mg;
            m = mg > threshold ? S(sees) : S(seen);
            if (m == S(sees)) {
              ws_.visible[idx(nvis++)] = g;
              continue;
            }
          }
        }
        if (nh_ == static_cast<int>(ws_.horizon.size())) return -1;
        ws_.horizon[idx(nh_)] = ridge_key(ws_.facet_vertices[idx(f)], r);
        int back = 0;  // g's ridge towards f (the adjacency is symmetric)
        if (g >= 0)
          while (back < 5 && ws_.neighbours[idx(g)][idx(back)] != f) ++back;
        ws_.outside[idx(nh_)] = g < 0 ? -1 : 8 * g + back;
        // The plane through the ridge and p is in the span of the two normals at the ridge:
        // m_f n_g - m_g n_f (zero where there is no g). Checked in planes().
        Wrench<S>& n0 = ws_.cone_normals[idx(nh_++)];
        if (g >= 0) {
          n0 = ws_.margins[idx(f)] * normal(g) - ws_.margins[idx(g)] * normal(f);
          n0 /= n0.norm();
        } else {
          n0.setZero();
        }
      }
    }
    if (table_slots(nh_) > ws_.ridges.size()) return -1;
    nvis_ = nvis;
    return nvis;
  }

  /// Replaces the facets of the last find_visible() by those joining vertex np (larger than
  /// every other index) to its horizon; the caller has checked that they fit.
  void replace_visible(int np) {
    const int nvis = nvis_, nh = nh_;
    for (int k = nvis; k < nh; ++k) ws_.visible[idx(k)] = count_ + (k - nvis);  // slots past the end
    count_ += std::max(0, nh - nvis);
    for (int k = 0; k < nvis; ++k) mark(ws_.visible[idx(k)]) = dead;
    for (int k = 0; k < nh; ++k) {
      std::array<int, 6>& v = ws_.facet_vertices[idx(ws_.visible[idx(k)])];
      const std::array<int, 5> r = ridge_vertices(ws_.horizon[idx(k)]);
      for (int m = 0; m < 5; ++m) v[idx(m)] = r[idx(m)];
      v[5] = np;
    }
    planes(nh, true);
    link(nh);
    // Fill the slots left dead (visible ones not reused, flat new ones) from the end.
    for (int k = 0; k < std::max(nvis, nh); ++k) {
      const int hole = ws_.visible[idx(k)];
      if (mark(hole) != dead) continue;
      while (count_ > 0 && mark(count_ - 1) == dead) --count_;
      if (hole < count_) move(--count_, hole);
    }
    while (count_ > 0 && mark(count_ - 1) == dead) --count_;
    pad();
  }

 private:
  static constexpr S dead = S(-1);  // the mark of a removed facet (live ones: >= 0)
  // The mark of facet f, kept in its plane's spare component (one cache line per facet).
  S& mark(int f) { return ws_.planes[idx(f)][7]; }

  // Offsets past the last facet, up to the next multiple of 8: never nearest.
  void pad() {
    for (int f = count_; f < (count_ + 7) / 8 * 8; ++f) ws_.offsets[idx(f)] = std::numeric_limits<S>::max();
  }

  // Slots of the ridge table for the cone of nh new facets: a power of two, at least 5 nh
  // (each ridge through p is met twice: at most half full).
  static std::size_t table_slots(int nh, int* shift = nullptr) {
    std::size_t slots = 16;
    int bits = 4;
    while (slots < 5 * static_cast<std::size_t>(nh)) slots *= 2, ++bits;
    if (shift != nullptr) *shift = 64 - bits;
    return slots;
  }

  // Views of facets slots[0 ..) as if they were 0 .. for facet_normals().
  struct SlotVertices {
    const Workspace& ws;
    const int* slots;
    const std::array<int, 6>& operator[](std::size_t k) const { return ws.facet_vertices[idx(slots[k])]; }
  };
  struct SlotNormals {
    struct Component {
      Workspace& ws;
      const int* slots;
      std::size_t i;
      S& operator[](std::size_t k) const { return ws.planes[idx(slots[k])][i]; }
    };
    Workspace& ws;
    const int* slots;
    Component operator[](std::size_t i) const { return Component{ws, slots, i}; }
  };

  // The facets ws.visible[0 .. n), their vertex lists set, get their planes, oriented away
  // from the centre, and the mark of a live facet; flat ones are marked dead. Returns how
  // many were flat. For a cone (vertex 5 the added point), the candidate normals of
  // find_visible() are kept where they pass the check of the file comment; the rest, or all
  // if not a cone, come from facet_normals().
  int planes(int n, bool cone) {
    int nrej = n;
    const int* rej = ws_.visible.data();
    if (cone) {  // |n0 . e| <= 4 u |e| = 2 eps |e| for each edge e from the added point
      nrej = 0;
      const S tol2 = S(4) * std::numeric_limits<S>::epsilon() * std::numeric_limits<S>::epsilon();
      for (int k = 0; k < n; ++k) {
        const int f = ws_.visible[idx(k)];
        const std::array<int, 6>& fv = ws_.facet_vertices[idx(f)];
        const Wrench<S>& n0 = ws_.cone_normals[idx(k)];
        const Wrench<S>& pv = ws_.vertices[idx(fv[5])];
        bool ok = n0.squaredNorm() > S(0.5);
        for (int j = 0; j < 5; ++j) {
          const Wrench<S> e = ws_.vertices[idx(fv[idx(j)])] - pv;
          const S r = n0.dot(e);
          ok = ok && r * r <= tol2 * e.squaredNorm();
        }
        if (ok) {
          for (int i = 0; i < 6; ++i) ws_.planes[idx(f)][idx(i)] = n0[i];
        } else {
          ws_.rejects[idx(nrej++)] = f;
        }
      }
      rej = ws_.rejects.data();
    }
    SlotNormals normals{ws_, rej};
    facet_normals<16>(ws_.vertices.data(), SlotVertices{ws_, rej}, 0, nrej, normals);
    int flat = 0;
    for (int k = 0; k < n; ++k) {
      const int f = ws_.visible[idx(k)];
      std::array<S, 8>& pl = ws_.planes[idx(f)];
      const Wrench<S> nrm = normal(f);
      const S off = nrm.dot(ws_.vertices[idx(ws_.facet_vertices[idx(f)][0])]);
      const S c = nrm.dot(centre_) - off;
      if (!(std::abs(c) > flat_)) {
        mark(f) = dead;
        ++flat;
        continue;
      }
      const S sign = std::copysign(S(1), -c);
      pl[6] = sign * off;
      ws_.offsets[idx(f)] = pl[6];
      for (int i = 0; i < 6; ++i) pl[idx(i)] *= sign;
      mark(f) = S(0);
    }
    return flat;
  }

  // The adjacency of the nh new facets ws.visible[0 .. nh) (vertex np last in each): across
  // ridge 5 the horizon's outside facet, which points back; across ridges 0 .. 4 (each
  // through np) the new facet with the same ridge, matched in a hash table of ridge keys. A
  // ridge left unmatched (a flat facet dropped, or a pinched horizon) gets -1.
  void link(int nh) {
    int shift = 0;
    const std::size_t slots = table_slots(nh, &shift);
    constexpr std::uint64_t empty = ~std::uint64_t(0);
    std::fill(ws_.ridges.begin(), ws_.ridges.begin() + static_cast<std::ptrdiff_t>(slots), RidgeEntry{empty, -1});
    for (int k = 0; k < nh; ++k) {
      const int f = ws_.visible[idx(k)];
      const bool live = mark(f) != dead;
      const int out = ws_.outside[idx(k)];
      if (out >= 0) ws_.neighbours[idx(out / 8)][idx(out % 8)] = live ? f : -1;
      if (!live) continue;
      std::array<int, 6>& nb = ws_.neighbours[idx(f)];
      nb[5] = out < 0 ? -1 : out / 8;
      for (int m = 0; m < 5; ++m) {
        nb[idx(m)] = -1;
        const std::uint64_t key = ridge_key(ws_.facet_vertices[idx(f)], m);
        std::size_t h = static_cast<std::size_t>((key * 0x9e3779b97f4a7c15u) >> shift);
        while (true) {
          RidgeEntry& e = ws_.ridges[h];
          if (e.key == empty) {  // first of the pair: wait for the other
            e = RidgeEntry{key, 8 * f + m};
            break;
          }
          if (e.key == key && e.owner >= 0) {  // second: link both
            nb[idx(m)] = e.owner / 8;
            ws_.neighbours[idx(e.owner / 8)][idx(e.owner % 8)] = f;
            e.owner = -1;  // matched (a third one starts a new pair)
            break;
          }
          h = (h + 1) & (slots - 1);
        }
      }
    }
  }

  // Moves live facet `from` to dead slot `to`: its neighbours follow.
  void move(int from, int to) {
    ws_.facet_vertices[idx(to)] = ws_.facet_vertices[idx(from)];
    ws_.planes[idx(to)] = ws_.planes[idx(from)];
    ws_.offsets[idx(to)] = ws_.offsets[idx(from)];
    ws_.neighbours[idx(to)] = ws_.neighbours[idx(from)];
    mark(from) = dead;
    for (int r = 0; r < 6; ++r) {
      const int g = ws_.neighbours[idx(to)][idx(r)];
      if (g < 0) continue;
      for (int s = 0; s < 6; ++s)
        if (ws_.neighbours[idx(g)][idx(s)] == from) ws_.neighbours[idx(g)][idx(s)] = to;
    }
  }

  Workspace& ws_;
  Wrench<S> centre_;
  S flat_;
  int count_{0};
  int nvis_{0};   // visible facets of the last find_visible()
  int nh_{0};     // its horizon ridges
  int stamp_{0};  // marks of the current search: stamp_ (tested) and stamp_ + 1 (visible)
};

}  // namespace detail
}  // namespace grip
