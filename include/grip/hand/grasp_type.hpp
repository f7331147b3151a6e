#pragma once
/// \file
/// Grasp types and their contribution tables d of eq. 8: the paper's Table 1 for the
/// cylindrical power grip, and four more from published grip-force measurements and statics.
/// Sources, derivations and the shares' convention: docs/hand.md, "Grasp types".

#include "grip/hand/squeeze.hpp"

namespace grip {

/// A grasp type: which phalanges squeeze the object, and how hard relative to each other.
enum class GraspType {
  CylindricalPower,  ///< the whole hand round a cylinder (the paper's Table 1)
  SphericalPower,    ///< the whole hand round a ball, the palm under it
  TipPinch,          ///< the thumb's and the index's distal pads against each other
  Tripod,            ///< the thumb's distal pad against the index's and long finger's
  LateralPinch,      ///< the thumb's distal pad against the radial side of the index's middle phalanx
};

/// The number of GraspType values.
constexpr int grasp_type_count = 5;

/// A short English name of the grasp type, for logs ("cylindrical power", ...).
constexpr const char* to_string(GraspType t) {
  switch (t) {
    case GraspType::CylindricalPower: return "cylindrical power";
    case GraspType::SphericalPower: return "spherical power";
    case GraspType::TipPinch: return "tip pinch";
    case GraspType::Tripod: return "tripod";
    case GraspType::LateralPinch: return "lateral pinch";
  }
  return "unknown";
}

namespace detail {

/// A ContributionTable of Scalar from shares written in double, [finger][phalanx] and the palm.
template <class Scalar>
constexpr ContributionTable<Scalar> contribution_table_of(const double (&d)[5][3], double palm) {
  ContributionTable<Scalar> t{};
  for (int f = 0; f < 5; ++f)
    for (int p = 0; p < 3; ++p) t.share[f][p] = Scalar(d[f][p]);
  t.palm = Scalar(palm);
  return t;
}

}  // namespace detail

/// The contribution table d of a grasp type. In every table the four fingers' shares sum to 1
/// (within 0.002, the rounding to three decimals) and the thumb and palm are in the same unit
/// (see ContributionTable). An unknown value gives the cylindrical power grip.
template <class Scalar = double>
constexpr ContributionTable<Scalar> contribution_table(GraspType t) {
  switch (t) {
    case GraspType::CylindricalPower: return cylindrical_power_grip<Scalar>();
    case GraspType::SphericalPower:
      // Finger and thumb totals from circular-grip measurements (Kinoshita et al. 1996),
      // rescaled to the four fingers; each finger split over its phalanges as in Table 1.
      return detail::contribution_table_of<Scalar>({{0.230, 0, 0.383},       // thumb
                                                    {0.069, 0.013, 0.095},   // index
                                                    {0.081, 0.015, 0.114},   // long
                                                    {0.119, 0.022, 0.165},   // ring
                                                    {0.119, 0.022, 0.165}},  // little
                                                   0.400);                   // palm
    case GraspType::TipPinch:
      // Two pads on one line: equilibrium makes their normal forces equal.
      return detail::contribution_table_of<Scalar>({{0, 0, 1}, {0, 0, 1}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, 0);
    case GraspType::Tripod:
      // The thumb against two mirror-symmetric pads (Baud-Bovy and Soechting 2001): half each.
      return detail::contribution_table_of<Scalar>({{0, 0, 1}, {0, 0, 0.5}, {0, 0, 0.5}, {0, 0, 0}, {0, 0, 0}}, 0);
    case GraspType::LateralPinch:
      // The thumb's pad against the index's middle phalanx (the key pinch), on one line.
      return detail::contribution_table_of<Scalar>({{0, 0, 1}, {0, 1, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, 0);
  }
  return cylindrical_power_grip<Scalar>();
}

}  // namespace grip
