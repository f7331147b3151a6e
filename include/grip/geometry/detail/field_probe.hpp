#pragma once
/// \file
/// How the narrow phase (narrow_phase.hpp) asks an object's distance field: the optional
/// abilities a field may offer, detected at compile time (parts, a bounded query, a segment
/// query), and the per-phalanx probe that carries a bounded query's hint from one point to the
/// next.

#include <type_traits>
#include <utility>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/types.hpp"

namespace grip {
namespace detail {

/// Fields made of parts (a Shape's primitives) give each sample one candidate per part with
/// PerPhalanx > 1, so that a phalanx lying in a groove between two parts touches both walls.
/// A field opts in with `static constexpr int max_parts`, `int part_count() const` and
/// `Scalar part_distance(int, const Vector3&, Vector3&) const`.
template <class Field, class = void>
struct field_parts {
  static constexpr int max = 1;
};
template <class Field>
struct field_parts<Field,
                   std::void_t<decltype(Field::max_parts), decltype(std::declval<const Field&>().part_count())>> {
  static constexpr int max = Field::max_parts;
};

/// Fields with a bounded, warm-started query (MeshShape::distance_within) let the narrow
/// phase skip, cheaply, the samples farther than its band from the surface:
///   bool distance_within(const Vector3& p, Scalar limit, Scalar& phi, Vector3& normal, int& hint) const;
template <class Field, class Scalar, class = void>
struct has_bounded_query : std::false_type {};
template <class Field, class Scalar>
struct has_bounded_query<Field, Scalar,
                         std::void_t<decltype(std::declval<const Field&>().distance_within(
                             std::declval<const Vector3<Scalar>&>(), Scalar(0), std::declval<Scalar&>(),
                             std::declval<Vector3<Scalar>&>(), std::declval<int&>()))>> : std::true_type {};

/// Fields whose bounded query names the nearest triangle (MeshShape::segment_distance2) are
/// refined triangle by triangle (refine()):
///   Scalar segment_distance2(int hint, const Vector3& p0, const Vector3& p1, Scalar& u) const;
template <class Field, class Scalar, class = void>
struct has_segment_query : std::false_type {};
template <class Field, class Scalar>
struct has_segment_query<
    Field, Scalar,
    std::void_t<decltype(std::declval<const Field&>().segment_distance2(
        0, std::declval<const Vector3<Scalar>&>(), std::declval<const Vector3<Scalar>&>(), std::declval<Scalar&>()))>>
    : std::true_type {};

/// The field as the narrow phase queries it, per phalanx: exact(p) is the field's distance;
/// within(p, limit) may answer false for a point farther than limit from the surface (only
/// fields with a bounded query do; the others always answer, exactly).
template <class Scalar, class Field, bool Bounded = has_bounded_query<Field, Scalar>::value>
struct FieldProbe {
  static constexpr bool bounded = false;
  static constexpr bool segments = false;
  const Field& field;
  int place() const { return -1; }
  void start_at(int) {}
  Scalar exact(const Vector3<Scalar>& p, Vector3<Scalar>& n) { return field.distance(p, n); }
  bool within(const Vector3<Scalar>& p, Scalar, Scalar& phi, Vector3<Scalar>& n) {
    phi = field.distance(p, n);
    return true;
  }
};
template <class Scalar, class Field>
struct FieldProbe<Scalar, Field, true> {
  static constexpr bool bounded = true;
  static constexpr bool segments = has_segment_query<Field, Scalar>::value;
  const Field& field;
  int hint{-1};  // the previous answer's place in the field: successive points are near
  int place() const { return hint; }
  void start_at(int place) { hint = place; }
  Scalar exact(const Vector3<Scalar>& p, Vector3<Scalar>& n) {
    Scalar phi = Scalar(0);
    if (field.distance_within(p, ScalarTraits<Scalar>::max_magnitude, phi, n, hint)) return phi;
    hint = -1;
    return field.distance(p, n);
  }
  bool within(const Vector3<Scalar>& p, Scalar limit, Scalar& phi, Vector3<Scalar>& n) {
    return field.distance_within(p, limit, phi, n, hint);
  }
};

}  // namespace detail
}  // namespace grip
