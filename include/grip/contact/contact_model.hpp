#pragma once
/// \file
/// Contact models as policy types: FrictionlessPoint, HardFinger, SoftFinger.
///
/// A model fixes what a contact can transmit. Each policy provides, for a Contact c:
/// - `dim`: unknowns per contact (1, 3 or 4), in grip's order (docs/conventions.md);
/// - `basis(c)`: the 6 x dim block G_i of the grasp matrix (eq. 3 for HardFinger);
/// - `target(c)`: the dim-vector t_i that F2 pulls x_i towards (eq. 7);
/// - `wrench(c, x)`: G_i x, the wrench the contact applies on the object;
/// - `wrench_transpose(c, l)`: G_i^T l, for a 6-vector l;
/// - `accumulate(acc, c, k)`: adds k G_i G_i^T to a GramAccumulator (closed forms);
/// - `identity_force_block`: true when accumulate() leaves the force rows in the closed form
///   [[k0 I, -[s1]x], [[s1]x, ...]] (GramAccumulator::extra only in the moment block), so that
///   solvers can eliminate the force rows in closed form and factor a 3x3 Schur complement.

#include <Eigen/Geometry>

#include "grip/contact/contact.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// Sums from which `sum_i k_i G_i G_i^T` (6x6) is assembled, so that each contact costs
/// a handful of flops (hard finger: ~20) instead of a 6x6 outer product.
///
/// For G_i = [I; [r]x] the block is [[I, -[r]x], [[r]x, |r|^2 I - r r^T]]; so
/// sum k G G^T = [[k0 I, -[s1]x], [[s1]x, S2]] + extra, with k0 = sum k, s1 = sum k r,
/// S2 = sum k (|r|^2 I - r r^T) (upper triangle kept). `extra` holds terms that are not of
/// this form.
template <class Scalar>
struct GramAccumulator {
  Scalar k0{0};                                    ///< k0 = sum k: the force block is k0 I
  Vector3<Scalar> s1{Vector3<Scalar>::Zero()};     ///< s1 = sum k r: the coupling blocks are -[s1]x, [s1]x
  Matrix3<Scalar> s2{Matrix3<Scalar>::Zero()};     ///< S2 = sum k (|r|^2 I - r r^T), upper triangle only
  Matrix6<Scalar> extra{Matrix6<Scalar>::Zero()};  ///< the terms not of that form, full 6x6

  /// The diagonal of matrix(), without forming it.
  Wrench<Scalar> diagonal() const {
    Wrench<Scalar> d = extra.diagonal();
    d.template head<3>().array() += k0;
    d.template tail<3>() += s2.diagonal();
    return d;
  }

  /// The assembled symmetric 6x6 matrix.
  Matrix6<Scalar> matrix() const {
    Matrix6<Scalar> m = extra;
    add_closed_form(m, k0, s1, s2);
    return m;
  }

  /// m += [[k0 I, -[s1]x], [[s1]x, S2]], S2 read from the upper triangle of `s2`: the
  /// closed-form part added to the other terms (matrix(), and solve_constrained's pass, which
  /// sums the parts apart and assembles them in place).
  /// Entry by entry (no temporaries: it runs under every pass of solve_constrained).
  static void add_closed_form(Matrix6<Scalar>& m, Scalar k0, const Vector3<Scalar>& s1, const Matrix3<Scalar>& s2) {
    const Scalar x = s1.x(), y = s1.y(), z = s1.z();
    for (int i = 0; i < 3; ++i) m(i, i) += k0;
    // [s1]x = [[0, -z, y], [z, 0, -x], [-y, x, 0]]: subtracted top right, added bottom left.
    m(0, 4) += z;
    m(0, 5) -= y;
    m(1, 3) -= z;
    m(1, 5) += x;
    m(2, 3) += y;
    m(2, 4) -= x;
    m(3, 1) -= z;
    m(3, 2) += y;
    m(4, 0) += z;
    m(4, 2) -= x;
    m(5, 0) -= y;
    m(5, 1) += x;
    // S2 from its upper triangle (add_point_force fills only that).
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m(3 + i, 3 + j) += i <= j ? s2(i, j) : s2(j, i);
  }

  /// Adds k [I; [r]x][I; [r]x]^T: the hard-finger block in closed form (plain scalar code:
  /// 3-vectors are too short for SIMD to pay).
  void add_point_force(Scalar k, const Vector3<Scalar>& r) {
    const Scalar x = r.x(), y = r.y(), z = r.z();
    const Scalar kx = k * x, ky = k * y, kz = k * z;
    k0 += k;
    s1.x() += kx;
    s1.y() += ky;
    s1.z() += kz;
    const Scalar kxx = kx * x, kyy = ky * y, kzz = kz * z;
    s2(0, 0) += kyy + kzz;
    s2(1, 1) += kxx + kzz;
    s2(2, 2) += kxx + kyy;
    s2(0, 1) -= kx * y;
    s2(0, 2) -= kx * z;
    s2(1, 2) -= ky * z;
  }
};

/// Point contact without friction: transmits only a compressive force along the normal.
/// Unknown: the normal magnitude x (N); f = x a. G_i = [a; r x a] (6x1). Target t_i = s_i.
struct FrictionlessPoint {
  static constexpr int dim = 1;                        ///< the normal magnitude x (N)
  static constexpr bool identity_force_block = false;  ///< the whole block is in `extra`
  /// One contact's unknown x.
  template <class Scalar>
  using Vector = Eigen::Matrix<Scalar, dim, 1>;

  /// G_i = [a; r x a] (6 x 1): the wrench of a unit normal force.
  template <class Scalar>
  static Eigen::Matrix<Scalar, 6, dim> basis(const Contact<Scalar>& c) {
    Eigen::Matrix<Scalar, 6, dim> g;
    g.template head<3>() = c.normal;
    g.template tail<3>() = c.position.cross(c.normal);
    return g;
  }
  /// t_i = s_i (N).
  template <class Scalar>
  static Vector<Scalar> target(const Contact<Scalar>& c) {
    return Vector<Scalar>::Constant(c.squeeze);
  }
  /// G_i x = [x a; r x (x a)]: the wrench the contact applies on the object.
  template <class Scalar>
  static Wrench<Scalar> wrench(const Contact<Scalar>& c, const Vector<Scalar>& x) {
    return basis(c) * x;
  }
  /// G_i^T l = a . l_f + (r x a) . l_m, for a 6-vector l = [l_f; l_m].
  template <class Scalar>
  static Vector<Scalar> wrench_transpose(const Contact<Scalar>& c, const Wrench<Scalar>& l) {
    return basis(c).transpose() * l;
  }
  /// Adds k G_i G_i^T to acc.extra (a rank-one 6x6 update).
  template <class Scalar>
  static void accumulate(GramAccumulator<Scalar>& acc, const Contact<Scalar>& c, Scalar k) {
    const Eigen::Matrix<Scalar, 6, 1> g = basis(c);
    acc.extra.noalias() += (k * g) * g.transpose();
  }
};

/// Hard finger, the paper's model: point contact with Coulomb friction, transmits a force.
/// Unknown: f_i (N, 3). G_i = [I3; R_i], R_i = [r_i]x (eq. 3). Target t_i = s_i a_i.
struct HardFinger {
  static constexpr int dim = 3;                       ///< the force f_i (N)
  static constexpr bool identity_force_block = true;  ///< accumulate() is add_point_force() alone
  /// One contact's unknowns f_i.
  template <class Scalar>
  using Vector = Eigen::Matrix<Scalar, dim, 1>;

  /// G_i = [I3; [r_i]x] (6 x 3), eq. 3.
  template <class Scalar>
  static Eigen::Matrix<Scalar, 6, dim> basis(const Contact<Scalar>& c) {
    Eigen::Matrix<Scalar, 6, dim> g;
    g << Matrix3<Scalar>::Identity(), skew(c.position);
    return g;
  }
  /// t_i = s_i a_i (N): the squeeze along the inward normal.
  template <class Scalar>
  static Vector<Scalar> target(const Contact<Scalar>& c) {
    return c.squeeze * c.normal;
  }
  /// G_i f = [f; r_i x f]: the wrench the contact applies on the object.
  template <class Scalar>
  static Wrench<Scalar> wrench(const Contact<Scalar>& c, const Vector<Scalar>& f) {
    const Scalar rx = c.position.x(), ry = c.position.y(), rz = c.position.z();
    Wrench<Scalar> w;
    w(0) = f.x();
    w(1) = f.y();
    w(2) = f.z();
    w(3) = ry * f.z() - rz * f.y();
    w(4) = rz * f.x() - rx * f.z();
    w(5) = rx * f.y() - ry * f.x();
    return w;
  }
  /// G_i^T l = l_f - r_i x l_m, for a 6-vector l = [l_f; l_m].
  template <class Scalar>
  static Vector<Scalar> wrench_transpose(const Contact<Scalar>& c, const Wrench<Scalar>& l) {
    // [I, R^T] l = l_f - r x l_m
    const Scalar rx = c.position.x(), ry = c.position.y(), rz = c.position.z();
    return Vector<Scalar>(l(0) - (ry * l(5) - rz * l(4)), l(1) - (rz * l(3) - rx * l(5)),
                          l(2) - (rx * l(4) - ry * l(3)));
  }
  /// Adds k G_i G_i^T in closed form (GramAccumulator::add_point_force).
  template <class Scalar>
  static void accumulate(GramAccumulator<Scalar>& acc, const Contact<Scalar>& c, Scalar k) {
    acc.add_point_force(k, c.position);
  }
};

/// Soft finger: a hard finger that also transmits a moment about the normal.
/// Unknowns: f_i (N, 3) then the torsional moment m_i (N m). G_i = [[I3, 0], [R_i, a_i]] (6x4).
/// Target t_i = (s_i a_i, 0): no torsion is asked for.
struct SoftFinger {
  static constexpr int dim = 4;                       ///< f_i (N), then m_i (N m)
  static constexpr bool identity_force_block = true;  ///< torsion adds to the moment block only
  /// One contact's unknowns (f_i, m_i).
  template <class Scalar>
  using Vector = Eigen::Matrix<Scalar, dim, 1>;

  /// G_i = [[I3, 0], [[r_i]x, a_i]] (6 x 4).
  template <class Scalar>
  static Eigen::Matrix<Scalar, 6, dim> basis(const Contact<Scalar>& c) {
    Eigen::Matrix<Scalar, 6, dim> g;
    g << Matrix3<Scalar>::Identity(), Vector3<Scalar>::Zero(), skew(c.position), c.normal;
    return g;
  }
  /// t_i = (s_i a_i, 0): no torsion is asked for.
  template <class Scalar>
  static Vector<Scalar> target(const Contact<Scalar>& c) {
    Vector<Scalar> t;
    t.template head<3>() = c.squeeze * c.normal;
    t(3) = Scalar(0);
    return t;
  }
  /// G_i x = [f; r_i x f + m a_i]: the wrench the contact applies on the object.
  template <class Scalar>
  static Wrench<Scalar> wrench(const Contact<Scalar>& c, const Vector<Scalar>& x) {
    Wrench<Scalar> w;
    const Vector3<Scalar> f = x.template head<3>();
    w.template head<3>() = f;
    w.template tail<3>() = c.position.cross(f) + x(3) * c.normal;
    return w;
  }
  /// G_i^T l = (l_f - r_i x l_m, a_i . l_m), for a 6-vector l = [l_f; l_m].
  template <class Scalar>
  static Vector<Scalar> wrench_transpose(const Contact<Scalar>& c, const Wrench<Scalar>& l) {
    Vector<Scalar> x;
    x.template head<3>() = l.template head<3>() - c.position.cross(l.template tail<3>());
    x(3) = c.normal.dot(l.template tail<3>());
    return x;
  }
  /// Adds k G_i G_i^T: the hard-finger closed form, plus k a_i a_i^T in the moment block of `extra`.
  template <class Scalar>
  static void accumulate(GramAccumulator<Scalar>& acc, const Contact<Scalar>& c, Scalar k) {
    acc.add_point_force(k, c.position);
    acc.extra.template bottomRightCorner<3, 3>().noalias() += (k * c.normal) * c.normal.transpose();
  }
};

}  // namespace grip
