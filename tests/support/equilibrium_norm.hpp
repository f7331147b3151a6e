#pragma once
// The equilibrium norm of solve_constrained, recomputed in double from its definition
// (docs/solve.md): |(f, m)|_L = |(f, m / L)|, L = max_i |r_i| the longest lever arm (1 when
// every contact is at the reference point), and its dual |(y_f, L y_m)| for multipliers and
// certificates.
#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <grip/core/scalar_traits.hpp>

namespace grip_test {

/// L of a grasp's contacts in double (any container of contacts with a `position`).
template <class Contacts>
double lever_length(const Contacts& contacts) {
  double l = 0;
  for (const auto& c : contacts) l = std::max(l, static_cast<double>(c.position.norm()));
  return l > 1e-15 ? l : 1.0;
}

/// L of a Grasp: 1 when every contact lies within 1 / ScalarTraits::max_magnitude of the
/// reference point, as the solver documents.
template <class GraspT>
double grasp_lever_length(const GraspT& g) {
  using S = typename GraspT::ScalarType;
  double l = 0;
  for (int i = 0; i < g.size(); ++i) l = std::max(l, static_cast<double>(g.contact(i).position.norm()));
  return l > 1.0 / static_cast<double>(grip::ScalarTraits<S>::max_magnitude) ? l : 1.0;
}

/// |(f, m / L)| of a wrench.
inline double norm_l(const Eigen::Matrix<double, 6, 1>& w, double l) {
  return std::sqrt(w.head<3>().squaredNorm() + w.tail<3>().squaredNorm() / (l * l));
}

/// |(y_f, L y_m)| of multipliers or a certificate.
inline double dual_norm_l(const Eigen::Matrix<double, 6, 1>& y, double l) {
  return std::sqrt(y.head<3>().squaredNorm() + y.tail<3>().squaredNorm() * l * l);
}

}  // namespace grip_test
