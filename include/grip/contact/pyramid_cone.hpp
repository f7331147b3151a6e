#pragma once
/// \file
/// The K-sided pyramid that linearises the Coulomb cone (inscribed or circumscribed).

#include <array>
#include <cmath>

#include "grip/contact/cone_support.hpp"
#include "grip/contact/contact.hpp"
#include "grip/core/index.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// How a PyramidCone sits against the exact Coulomb cone of the same mu.
enum class PyramidFit {
  Inscribed,      ///< edges on the exact cone: the pyramid lies inside it (conservative)
  Circumscribed,  ///< faces tangent to the exact cone: the pyramid contains it
};

/// A K-sided pyramid approximating the Coulomb cone {|f_t| <= mu f_n} about the unit inward
/// normal a (K >= 3). The tangent plane uses the deterministic TangentBasis (t1, t2) of a;
/// the pyramid's edges point along a + R (cos th_j t1 + sin th_j t2),
/// th_j = (2 j + h) pi / K, j = 0..K-1, with h = half_step() in {0, 1} (h = 1 turns the
/// pyramid by half a side; duals need it). Its faces are f_t . u_j <= r f_n with outward
/// tangential unit directions u_j at angles (2 j + 1 + h) pi / K.
///
/// Radii (tangential, per newton of normal force) and worst-case error against the exact cone:
/// - Inscribed: circumradius R = mu, inradius r = mu cos(pi/K). Every force of the pyramid is in
///   the exact cone; a force on the exact cone's boundary can lie outside the pyramid by up to
///   mu (1 - cos(pi/K)) f_n of tangential load (29.3% of mu f_n for K = 4, 7.6% for K = 8).
/// - Circumscribed: inradius r = mu, circumradius R = mu / cos(pi/K). The pyramid contains the
///   exact cone and reaches up to |f_t| = mu f_n / cos(pi/K) at its edges: up to
///   mu (1/cos(pi/K) - 1) f_n too much (41.4% for K = 4, 8.2% for K = 8).
///
/// Margin (N): r f_n - max_j f_t . u_j, i.e. the tangential load that can still be added
/// towards the nearest face; for f_n < 0 the pull correction min(., f_n). Invalid input
/// follows cone_support.hpp. Preconditions: |a| = 1, mu >= 0 finite.
template <int K, class Scalar, PyramidFit Fit = PyramidFit::Inscribed>
class PyramidCone {
  static_assert(K >= 3, "a pyramid needs at least 3 sides");

 public:
  using ScalarType = Scalar;                   ///< the scalar type (float or double)
  static constexpr int dim = 3;                ///< size of the contact unknown
  static constexpr int sides = K;              ///< number of faces (and edges)
  static constexpr PyramidFit fit = Fit;       ///< inscribed or circumscribed
  using Vector = Eigen::Matrix<Scalar, 3, 1>;  ///< a contact force f (N)
  /// The type of dual(): the other fit.
  using DualType =
      PyramidCone<K, Scalar, Fit == PyramidFit::Inscribed ? PyramidFit::Circumscribed : PyramidFit::Inscribed>;

  /// The pyramid about the z axis with mu = 0 (a ray).
  PyramidCone() : PyramidCone(Vector3<Scalar>::UnitZ(), Scalar(0), 0) {}

  /// The pyramid about unit normal a for friction coefficient mu, turned by half_step (0 or 1,
  /// other values taken modulo 2) half sides.
  PyramidCone(const Vector3<Scalar>& a, Scalar mu, int half_step = 0)
      : normal_(a), basis_(TangentBasis<Scalar>::from_normal(a)), mu_(mu), half_(((half_step % 2) + 2) % 2) {
    const Scalar c = angle_cos(1);  // cos(pi/K)
    r_ = Fit == PyramidFit::Inscribed ? mu * c : mu;
    big_r_ = Fit == PyramidFit::Inscribed ? mu : mu / c;
  }

  /// The inscribed/circumscribed (per Fit) pyramid of contact c: a = c.normal, mu = c.friction.
  static PyramidCone from_contact(const Contact<Scalar>& c) { return PyramidCone(c.normal, c.friction, 0); }

  const Vector3<Scalar>& normal() const { return normal_; }     ///< a
  Scalar mu() const { return mu_; }                             ///< the nominal friction coefficient
  int half_step() const { return half_; }                       ///< 0 or 1
  const TangentBasis<Scalar>& basis() const { return basis_; }  ///< (t1, t2)
  Scalar inner_radius() const { return r_; }                    ///< r (see class comment)
  Scalar outer_radius() const { return big_r_; }                ///< R (see class comment)

  /// f_n = f.a (N).
  Scalar normal_part(const Vector& f) const { return f.dot(normal_); }
  /// f_t = f - (f.a) a (N).
  Vector3<Scalar> tangential_part(const Vector& f) const { return f - normal_part(f) * normal_; }
  /// |f_t| (N).
  Scalar tangential_norm(const Vector& f) const { return tangential_part(f).norm(); }
  /// The largest tangential load against a face, max_j f_t . u_j (N), >= |f_t| cos(pi/K).
  Scalar face_load(const Vector& f) const {
    const Scalar u = f.dot(basis_.t1), v = f.dot(basis_.t2);
    Scalar m = u * angle_cos(1 + half_) + v * angle_sin(1 + half_);
    for (int j = 1; j < K; ++j) {
      const int k = 2 * j + 1 + half_;
      const Scalar l = u * angle_cos(k) + v * angle_sin(k);
      if (l > m) m = l;
    }
    return m;
  }

  /// True iff f satisfies every face inequality. False for invalid f.
  bool is_inside(const Vector& f) const { return margin(f) >= Scalar(0); }

  /// Signed margin (N): r f_n - face_load(f), pull-corrected for f_n < 0.
  Scalar margin(const Vector& f) const {
    if (!detail::cone_input_valid(f)) return cone_margin_floor<Scalar>();
    return margin_of(normal_part(f), face_load(f));
  }

  /// Relative margin 1 - face_load / (r f_n), with CoulombCone's conventions (1 for no
  /// tangential load with f_n > 0, 0 for f = 0, cone_margin_floor() for f_n <= 0 otherwise).
  Scalar relative_margin(const Vector& f) const {
    if (!detail::cone_input_valid(f)) return cone_margin_floor<Scalar>();
    const Scalar fn = normal_part(f);
    return relative_of(fn, face_load(f), fn <= Scalar(0) && tangential_norm(f) == Scalar(0));
  }

  /// The monitor's slip test: margin(x) < -slack, for a valid x with f_n > 0 and slack >= 0 (N).
  bool slips(const Vector& x, Scalar slack) const { return margin(x) < -slack; }

  /// normal_part, tangential_part, margin and relative_margin of f in one pass.
  ConeMeasure<Scalar> measure(const Vector& f) const {
    ConeMeasure<Scalar> m;
    if (!detail::cone_input_valid(f)) return m;
    m.normal_force = normal_part(f);
    m.tangential_force = f - m.normal_force * normal_;
    m.tangential_norm = m.tangential_force.norm();
    const Scalar load = face_load(f);
    m.margin = margin_of(m.normal_force, load);
    m.relative_margin = relative_of(m.normal_force, load, m.tangential_norm == Scalar(0));
    return m;
  }

  /// Euclidean projection onto the pyramid: f if inside; else the nearest of the finitely many
  /// face candidates (apex, K edge rays, K faces), O(K) closed form. mu = 0: max(f_n, 0) a.
  /// Invalid f gives 0.
  Vector project(const Vector& f) const {
    if (!detail::cone_input_valid(f)) return Vector::Zero();
    if (is_inside(f)) return f;
    if (!(mu_ > Scalar(0))) {
      const Scalar fn = normal_part(f);
      return fn > Scalar(0) ? Vector(fn * normal_) : Vector(Vector::Zero());
    }
    std::array<Vector3<Scalar>, detail::idx(K)> e;
    const Scalar scale = Scalar(1) / std::sqrt(Scalar(1) + big_r_ * big_r_);
    for (std::size_t j = 0; j < detail::idx(K); ++j)
      e[j] = scale * normal_ + (scale * big_r_) * (angle_cos(2 * static_cast<int>(j) + half_) * basis_.t1 +
                                                   angle_sin(2 * static_cast<int>(j) + half_) * basis_.t2);
    return detail::project_onto_edge_cone(f, e);
  }

  /// The dual cone {y : y.x >= 0 for all x in the pyramid}: the pyramid with faces normal to
  /// this one's edges, i.e. the other fit for 1/mu, turned by K + 1 half sides (mu = 0 maps to
  /// cone_half_space_mu() and back, as for CoulombCone). Dual of Inscribed(mu) is
  /// Circumscribed(1/mu) and vice versa.
  DualType dual() const { return DualType(normal_, detail::dual_coefficient(mu_), (half_ + K + 1) % 2); }

 private:
  /// cos and sin of k pi / K for k = 0..2K (taken modulo 2K), computed once per program.
  struct AngleTable {
    std::array<Scalar, 2 * detail::idx(K)> c{}, s{};
    AngleTable() {
      const long double pi = 3.14159265358979323846264338327950288L;
      for (int k = 0; k < 2 * K; ++k) {
        const long double a = static_cast<long double>(k) * pi / static_cast<long double>(K);
        c[detail::idx(k)] = static_cast<Scalar>(std::cos(a));
        s[detail::idx(k)] = static_cast<Scalar>(std::sin(a));
      }
    }
  };
  static const AngleTable& table() {
    static const AngleTable t;
    return t;
  }
  static Scalar angle_cos(int k) { return table().c[detail::idx(k % (2 * K))]; }
  static Scalar angle_sin(int k) { return table().s[detail::idx(k % (2 * K))]; }

  Scalar margin_of(Scalar fn, Scalar load) const { return detail::pull_corrected(r_ * fn - load, fn); }
  Scalar relative_of(Scalar fn, Scalar load, bool no_tangential) const {
    if (fn <= Scalar(0)) return (fn == Scalar(0) && no_tangential) ? Scalar(0) : cone_margin_floor<Scalar>();
    return load <= Scalar(0) ? Scalar(1) : detail::relative_from(load, r_ * fn);
  }

  Vector3<Scalar> normal_;
  TangentBasis<Scalar> basis_;
  Scalar mu_;
  int half_;
  Scalar r_{0};
  Scalar big_r_{0};
};

}  // namespace grip
