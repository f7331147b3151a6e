#pragma once
/// \file
/// The primitive wrenches of ferrari_canny_epsilon() (analysis/epsilon.hpp): internal
/// (grip::detail), may change. The definitions are those of epsilon.hpp's file comment.

#include <array>
#include <cmath>

#include "grip/contact/contact.hpp"
#include "grip/core/index.hpp"
#include "grip/core/types.hpp"

namespace grip {
namespace detail {

/// A fixed orthonormal tangent basis (t1, t2) of the plane normal to unit a: t1 = a x e / |a x e|
/// with e the x axis, or the y axis when |a_x| > 0.9; t2 = a x t1. (Not contact/'s TangentBasis,
/// which crosses with the axis of a's smallest component: the pyramid's sides, and so epsilon's
/// linearisation, would turn.)
template <class S>
void tangent_basis(const Vector3<S>& a, Vector3<S>& t1, Vector3<S>& t2) {
  const Vector3<S> e = std::abs(a.x()) > S(0.9) ? Vector3<S>::UnitY() : Vector3<S>::UnitX();
  t1 = a.cross(e).normalized();
  t2 = a.cross(t1);
}

/// Number of primitive wrenches per contact for K pyramid sides: K (hard), K + 2 (soft), 1.
template <class Model, int K>
constexpr int primitives_per_contact() {
  return Model::dim == 1 ? 1 : (Model::dim == 4 ? K + 2 : K);
}

/// Writes the primitive wrenches of contact c (see epsilon.hpp's file comment) into
/// out[0..count) and returns count, primitives_per_contact<Model, K>().
template <class Model, int K, class S>
int contact_primitives(const Contact<S>& c, S lever, Wrench<S>* out) {
  const Vector3<S> a = c.normal;
  auto put = [&](int j, const Vector3<S>& d, S m) {
    out[j].template head<3>() = d;
    out[j].template tail<3>() = (c.position.cross(d) + m * a) / lever;
  };
  if constexpr (Model::dim == 1) {
    put(0, a, S(0));
    return 1;
  } else {
    Vector3<S> t1, t2;
    tangent_basis(a, t1, t2);
    const S two_pi = S(6.283185307179586476925L);
    for (int k = 0; k < K; ++k) {
      const S th = two_pi * S(k) / S(K);
      put(k, a + c.friction * (std::cos(th) * t1 + std::sin(th) * t2), S(0));
    }
    if constexpr (Model::dim == 4) {
      put(K, a, c.torsional_friction);
      put(K + 1, a, -c.torsional_friction);
      return K + 2;
    }
    return K;
  }
}

}  // namespace detail
}  // namespace grip
