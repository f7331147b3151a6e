#pragma once
/// \file
/// Facet keys and facet normals of the epsilon search's inner polytope
/// (detail/epsilon_polytope.hpp): ridges packed into 64-bit keys, and the unit normals of
/// 5-simplices in wrench space computed 16 at a time in SIMD lanes. Internal (grip::detail),
/// may change.

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "grip/core/index.hpp"
#include "grip/core/types.hpp"

namespace grip {
namespace detail {

/// Ridge keys: five sorted vertex indices below 4096, 12 bits each, the first one highest, so
/// that keys order as the index lists do lexicographically.
constexpr int max_ridge_vertex = 4095;

/// The key of the ridge of sorted facet vertices f (6) without f[drop].
inline std::uint64_t ridge_key(const std::array<int, 6>& f, int drop) {
  std::uint64_t key = 0;
  for (int k = 0; k < 6; ++k)
    if (k != drop) key = (key << 12) | static_cast<std::uint64_t>(f[idx(k)]);
  return key;
}

/// The five sorted vertex indices of a ridge key.
inline std::array<int, 5> ridge_vertices(std::uint64_t key) {
  std::array<int, 5> r{};
  for (int m = 4; m >= 0; --m, key >>= 12) r[idx(m)] = static_cast<int>(key & 0xfffu);
  return r;
}

/// Unit normals of the hyperplanes through vertices[facet_vertices[f][0..6)] for f in
/// [first, first + count) (5-simplices in wrench space), written to normals[i][f], Lanes
/// facets at a time in SIMD lanes (several independent vectors per operation hide the latency
/// of the sequential projections): per facet, the edges from its first vertex are
/// orthonormalised by Gram-Schmidt, each projected out twice (which is enough for full
/// accuracy), and the normal is the coordinate axis with the largest residual against them,
/// projected the same way. An edge with nothing left is skipped (the simplex is flat there;
/// the normal is then one of several, as QR would give). A normal that is not finite comes
/// out as NaN.
template <int Lanes, class S, class FacetVertices, class Normals>
void facet_normals(const Wrench<S>* vertices, const FacetVertices& facet_vertices, int first, int count,
                   Normals& normals) {
  using A = Eigen::Array<S, Lanes, 1>;
  for (int f0 = first; f0 < first + count; f0 += Lanes) {
    const int lanes = first + count - f0 < Lanes ? first + count - f0 : Lanes;
    alignas(64) S edges[5][6][Lanes];  // edge k of each lane's facet, transposed
    for (int l = 0; l < Lanes; ++l) {  // padded lanes repeat the first facet
      const std::array<int, 6>& fv = facet_vertices[idx(f0 + (l < lanes ? l : 0))];
      const Wrench<S>& v0 = vertices[fv[0]];
      for (int k = 0; k < 5; ++k) {
        const Wrench<S>& vk = vertices[fv[idx(k + 1)]];
        for (int i = 0; i < 6; ++i) edges[k][i][l] = vk[i] - v0[i];
      }
    }
    std::array<std::array<A, 6>, 5> q;  // orthonormal edge directions (zero where skipped)
    std::array<A, 6> e;
    auto project_out = [&q, &e](int m) {
      for (int pass = 0; pass < 2; ++pass)
        for (int b = 0; b < m; ++b) {
          A d = q[idx(b)][0] * e[0];
          for (int i = 1; i < 6; ++i) d += q[idx(b)][idx(i)] * e[idx(i)];
          for (int i = 0; i < 6; ++i) e[idx(i)] -= d * q[idx(b)][idx(i)];
        }
    };
    for (int k = 0; k < 5; ++k) {
      for (int i = 0; i < 6; ++i) e[idx(i)] = Eigen::Map<const A, Eigen::Aligned>(edges[k][i]);
      project_out(k);
      A n2 = e[0] * e[0];
      for (int i = 1; i < 6; ++i) n2 += e[idx(i)] * e[idx(i)];
      const A inv = (n2 > S(0)).select(n2.sqrt().inverse(), A::Zero());
      for (int i = 0; i < 6; ++i) q[idx(k)][idx(i)] = e[idx(i)] * inv;
    }
    // The squared residual of axis i is 1 - sum_b q_b(i)^2: take the largest (first of ties).
    std::array<A, 6> left;
    A best = A::Constant(S(-1));
    for (int i = 0; i < 6; ++i) {
      left[idx(i)] = A::Ones();
      for (int b = 0; b < 5; ++b) left[idx(i)] -= q[idx(b)][idx(i)].square();
      best = best.max(left[idx(i)]);
    }
    A taken = A::Zero();
    for (int i = 0; i < 6; ++i) {
      e[idx(i)] = (left[idx(i)] >= best && taken == S(0)).select(A::Ones(), A::Zero());
      taken += e[idx(i)];
    }
    project_out(5);
    A n2 = e[0] * e[0];
    for (int i = 1; i < 6; ++i) n2 += e[idx(i)] * e[idx(i)];
    const A inv = n2.sqrt().inverse();
    for (int i = 0; i < 6; ++i)
      for (int l = 0; l < lanes; ++l) normals[idx(i)][idx(f0 + l)] = e[idx(i)][l] * inv[l];
  }
}

}  // namespace detail
}  // namespace grip
