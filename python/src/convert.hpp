#pragma once
// NumPy arrays in, grip's types out: shape and value checks that raise ValueError naming the
// field and the index, before anything reaches the library (whose own checks answer with a
// Status, not a message). Complex input, which a cast to double would reduce to its real parts,
// raises TypeError naming the argument: every array the bindings take is read by numbers(),
// every number by the type Real or Integer (below).

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <grip/grip.hpp>

namespace grip_python {

namespace py = pybind11;

/// Most contacts a grasp from Python holds (the bound of its fixed-capacity storage).
constexpr int max_contacts = 64;

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// The TypeError's message for complex values given as `name`.
inline std::string complex_error(const std::string& name) {
  return name + ": complex values are not accepted (imaginary parts would be dropped)";
}

/// True for an array of complex dtype.
inline bool complex_array(const py::handle& obj) {
  return py::isinstance<py::array>(obj) && py::reinterpret_borrow<py::array>(obj).dtype().kind() == 'c';
}

/// True for a complex number as a scalar: Python's complex, NumPy's complex scalars, or any
/// object whose `dtype` is complex (a 0-d or 1-element array, which a float conversion would
/// also reduce to its real part).
inline bool complex_scalar(const py::handle& obj) {
  if (PyFloat_Check(obj.ptr()) || PyLong_Check(obj.ptr())) return false;  // the common case, first
  if (PyComplex_Check(obj.ptr()) || complex_array(obj)) return true;
  if (!py::hasattr(obj, "dtype")) return false;
  const py::object dtype = obj.attr("dtype");
  return py::isinstance<py::dtype>(dtype) && py::reinterpret_borrow<py::dtype>(dtype).kind() == 'c';
}

/// The numbers of `obj` (an array, a sequence or a scalar) as a C-contiguous array of T, cast
/// as NumPy casts (a null array when it cannot: the caller's ValueError names the shape it
/// wants); TypeError naming `name` when they are complex. Every array argument of the
/// bindings is read through it.
template <class T = double>
py::array_t<T, py::array::c_style | py::array::forcecast> numbers(const py::handle& obj, const char* name) {
  using Out = py::array_t<T, py::array::c_style | py::array::forcecast>;
  if (PyFloat_Check(obj.ptr()) || PyLong_Check(obj.ptr())) return Out::ensure(obj);
  if (py::isinstance<py::array>(obj)) {
    if (complex_array(obj)) throw py::type_error(complex_error(name));
    return Out::ensure(obj);
  }
  // A sequence or another scalar: NumPy's own dtype for it first (a list holding one complex
  // number is complex), then the cast from that array.
  const py::array natural = py::array::ensure(obj);
  if (!natural) return Out::ensure(obj);
  if (complex_array(natural)) throw py::type_error(complex_error(name));
  return Out::ensure(natural);
}

/// A number argument of type T (double or int): what pybind11 takes for a T, except complex
/// numbers, which it would cast to their real parts (NumPy's complex scalars) or refuse without
/// naming the argument (Python's complex). get(name) is the value, or TypeError naming `name`
/// for a complex number. Declare the argument as Real or Integer and read it with get().
template <class T>
struct Number {
  T value{};
  bool complex{false};
  T get(const char* name) const {
    if (complex) throw py::type_error(complex_error(name));
    return value;
  }
};
using Real = Number<double>;
using Integer = Number<int>;

inline std::string shape_of(const Array& a) {
  std::string s = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

[[noreturn]] inline void invalid(const std::string& what) { throw py::value_error(what); }

/// An (n, 3) array of finite numbers within grip's magnitude bound.
inline Array rows3(const py::handle& obj, const char* name) {
  Array a = numbers(obj, name);
  if (!a) invalid(std::string(name) + " must be an array of numbers of shape (n, 3)");
  if (a.ndim() != 2 || a.shape(1) != 3) invalid(std::string(name) + " must have shape (n, 3), not " + shape_of(a));
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (int k = 0; k < 3; ++k) {
      const double v = a.at(i, k);
      if (!std::isfinite(v) || std::abs(v) > grip::ScalarTraits<double>::max_magnitude)
        invalid(std::string(name) + "[" + std::to_string(i) + "] is not finite (or beyond 1e15)");
    }
  return a;
}

/// A number per contact as given: a scalar (the same for all) or an array of shape (n,);
/// label(name, i) names contact i's value in messages (the bare name for a scalar).
struct PerContact {
  std::vector<double> values;
  bool scalar{false};
  std::string label(const char* name, std::size_t i) const {
    return scalar ? std::string(name) : std::string(name) + "[" + std::to_string(i) + "]";
  }
};

/// The n numbers of `obj`, a scalar or (n,), unchecked (ValueError for another shape).
inline PerContact per_contact_values(const py::handle& obj, py::ssize_t n, const char* name) {
  PerContact out;
  out.values.resize(static_cast<std::size_t>(n));
  Array a = numbers(obj, name);
  if (!a) invalid(std::string(name) + " must be a number or an array of shape (n,)");
  if (a.ndim() == 0) {
    out.scalar = true;
    for (double& v : out.values) v = a.at();
  } else if (a.ndim() == 1 && a.shape(0) == n) {
    for (py::ssize_t i = 0; i < n; ++i) out.values[static_cast<std::size_t>(i)] = a.at(i);
  } else {
    invalid(std::string(name) + " must be a number or have shape (" + std::to_string(n) + ",), not " + shape_of(a));
  }
  return out;
}

/// A number per contact: a scalar (the same for all) or an array of shape (n,), each finite
/// and at least `least`.
inline std::vector<double> per_contact(const py::handle& obj, py::ssize_t n, const char* name, double least,
                                       const char* bound) {
  const PerContact v = per_contact_values(obj, n, name);
  for (std::size_t i = 0; i < v.values.size(); ++i) {
    const double x = v.values[i];
    if (!std::isfinite(x) || std::abs(x) > grip::ScalarTraits<double>::max_magnitude)
      invalid(v.label(name, i) + " is not finite (or beyond 1e15)");
    if (!(x >= least)) invalid(v.label(name, i) + " must be " + bound + ", not " + std::to_string(x));
  }
  return v.values;
}

/// True for a valid Contact::max_normal_force (N): > 0 and within 1e15, or +inf (no bound).
inline bool valid_normal_force_bound(double x) {
  return x > 0 && (x <= grip::ScalarTraits<double>::max_magnitude || x == std::numeric_limits<double>::infinity());
}

/// What a ValueError says of an invalid max_normal_force `x`, named `at`.
inline std::string normal_force_bound_error(const std::string& at, double x) {
  return at + " must be > 0 (and at most 1e15, or inf for no bound), not " + std::to_string(x);
}

/// Contact::max_normal_force per contact: a scalar or (n,), each valid_normal_force_bound.
inline std::vector<double> normal_force_bounds(const py::handle& obj, py::ssize_t n, const char* name) {
  const PerContact v = per_contact_values(obj, n, name);
  for (std::size_t i = 0; i < v.values.size(); ++i)
    if (!valid_normal_force_bound(v.values[i])) invalid(normal_force_bound_error(v.label(name, i), v.values[i]));
  return v.values;
}

/// A wrench (force in N; moment in N m), shape (6,), finite.
inline grip::Wrench<double> wrench(const py::handle& obj, const char* name) {
  Array a = numbers(obj, name);
  if (!a || a.ndim() != 1 || a.shape(0) != 6)
    invalid(std::string(name) + " must have shape (6,) (force; moment), not " +
            (a ? shape_of(a) : std::string("a non-array")));
  grip::Wrench<double> w;
  for (int k = 0; k < 6; ++k) {
    w(k) = a.at(k);
    if (!std::isfinite(w(k)) || std::abs(w(k)) > grip::ScalarTraits<double>::max_magnitude)
      invalid(std::string(name) + "[" + std::to_string(k) + "] is not finite (or beyond 1e15)");
  }
  return w;
}

/// One contact from its numbers, checked; label() names it in messages ("[3]" or "[12, 3]"),
/// called only to raise. fmax: max_normal_force (> 0, +inf for no bound).
template <class Label>
grip::Contact<double> contact(const double* p, const double* a, double mu, double mut, double s, double w, double fmax,
                              const Label& label) {
  const auto finite = [&](double v, const char* field) {
    if (!std::isfinite(v) || std::abs(v) > grip::ScalarTraits<double>::max_magnitude)
      invalid(std::string(field) + label() + " is not finite (or beyond 1e15)");
  };
  for (int k = 0; k < 3; ++k) finite(p[k], "positions");
  for (int k = 0; k < 3; ++k) finite(a[k], "normals");
  finite(mu, "friction");
  finite(mut, "torsional_friction");
  finite(s, "squeeze");
  finite(w, "weights");
  if (!(mu >= 0)) invalid("friction" + label() + " must be >= 0, not " + std::to_string(mu));
  if (!(mut >= 0)) invalid("torsional_friction" + label() + " must be >= 0, not " + std::to_string(mut));
  if (!(s >= 0)) invalid("squeeze" + label() + " must be >= 0, not " + std::to_string(s));
  if (!(w >= grip::ScalarTraits<double>::min_weight))
    invalid("weights" + label() + " must be >= 1e-12, not " + std::to_string(w));
  if (!valid_normal_force_bound(fmax)) invalid(normal_force_bound_error("max_normal_force" + label(), fmax));
  grip::Contact<double> c;
  c.position = grip::Vector3<double>(p[0], p[1], p[2]);
  c.normal = grip::Vector3<double>(a[0], a[1], a[2]);
  c.friction = mu;
  c.torsional_friction = mut;
  c.squeeze = s;
  c.weight = w;
  c.max_normal_force = fmax;
  const double norm = c.normal.norm();
  if (!(std::abs(norm * norm - 1) <= 2 * grip::ScalarTraits<double>::normal_tolerance))
    invalid("normals" + label() + " must be a unit vector (to 1e-6), its norm is " + std::to_string(norm));
  if (grip::validate(c) != grip::Status::Ok) invalid("contact" + label() + " is invalid");
  return c;
}

/// The contacts of a grasp from its arrays, each checked (see grip::validate for the rules).
inline std::vector<grip::Contact<double>> contacts(const py::handle& positions, const py::handle& normals,
                                                   const py::handle& friction, const py::handle& torsional_friction,
                                                   const py::handle& squeeze, const py::handle& weights,
                                                   const py::handle& max_normal_force) {
  const Array p = rows3(positions, "positions"), a = rows3(normals, "normals");
  const py::ssize_t n = p.shape(0);
  if (a.shape(0) != n)
    invalid("normals must have as many rows as positions (" + std::to_string(n) + "), not " +
            std::to_string(a.shape(0)));
  if (n < 1 || n > max_contacts)
    invalid("a grasp has 1 to " + std::to_string(max_contacts) + " contacts, not " + std::to_string(n));
  const auto mu = per_contact(friction, n, "friction", 0.0, ">= 0");
  const auto mut = per_contact(torsional_friction, n, "torsional_friction", 0.0, ">= 0");
  const auto s = per_contact(squeeze, n, "squeeze", 0.0, ">= 0");
  const auto w = per_contact(weights, n, "weights", grip::ScalarTraits<double>::min_weight, ">= 1e-12");
  const auto fmax = normal_force_bounds(max_normal_force, n, "max_normal_force");
  std::vector<grip::Contact<double>> out;
  for (py::ssize_t i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    out.push_back(contact(p.data(i, 0), a.data(i, 0), mu[k], mut[k], s[k], w[k], fmax[k],
                          [i] { return "[" + std::to_string(i) + "]"; }));
  }
  return out;
}

/// A (3,) vector of finite numbers.
inline grip::Vector3<double> vec3(const py::handle& obj, const char* name) {
  const Array a = numbers(obj, name);
  if (!a || a.ndim() != 1 || a.shape(0) != 3) invalid(std::string(name) + " must have shape (3,)");
  const grip::Vector3<double> v(a.at(0), a.at(1), a.at(2));
  if (!v.allFinite()) invalid(std::string(name) + " is not finite");
  return v;
}

/// A rigid pose from a (4, 4) homogeneous matrix: finite, the rotation orthonormal to 1e-3,
/// the last row 0 0 0 1.
inline grip::Isometry3<double> pose(const py::handle& obj, const char* name) {
  const Array a = numbers(obj, name);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    invalid(std::string(name) + " must be a (4, 4) homogeneous matrix, not " + (a ? shape_of(a) : std::string("?")));
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = a.at(r, c);
  if (!m.allFinite()) invalid(std::string(name) + " must be finite and rigid (an orthonormal rotation, to 1e-3)");
  const Eigen::Matrix3d rot = m.topLeftCorner<3, 3>();
  if (!((rot.transpose() * rot - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-3) ||
      !(m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).isZero(0))
    invalid(std::string(name) + " must be rigid: an orthonormal rotation (to 1e-3) and a last row 0 0 0 1");
  grip::Isometry3<double> t = grip::Isometry3<double>::Identity();
  t.linear() = rot;
  t.translation() = m.topRightCorner<3, 1>();
  return t;
}

/// A finite vector of Size joint values (rad) named `name` in messages.
template <int Size>
Eigen::Matrix<double, Size, 1> joint_vector(const py::handle& obj, const char* name) {
  const Array a = numbers(obj, name);
  if (!a || a.ndim() != 1 || a.shape(0) != Size)
    invalid(std::string(name) + " must have shape (" + std::to_string(Size) +
            ",) (rad, the joint order of docs/hand.md), not " + (a ? shape_of(a) : std::string("?")));
  Eigen::Matrix<double, Size, 1> q;
  for (int k = 0; k < Size; ++k) {
    q(k) = a.at(k);
    if (!std::isfinite(q(k))) invalid(std::string(name) + "[" + std::to_string(k) + "] is not finite");
  }
  return q;
}

/// The whole hand's 20 joints (rad), finite.
inline grip::HandJoints<double> joints(const py::handle& obj) {
  return joint_vector<grip::hand_dof_count>(obj, "joints");
}

/// The 14 joint angles (rad), finite.
inline grip::JointAngles<double> angles(const py::handle& obj) {
  return joint_vector<grip::hand_joint_count>(obj, "angles");
}

}  // namespace grip_python

namespace pybind11 {
namespace detail {

/// Real and Integer from Python: a complex number is taken (and refused by get(), naming the
/// argument); anything else is loaded as pybind11 loads a double or an int, which keeps the
/// signatures' types (float, int) and pybind11's own TypeError for what is not a number.
template <class T>
struct type_caster<grip_python::Number<T>> {
  PYBIND11_TYPE_CASTER(grip_python::Number<T>, make_caster<T>::name);

  bool load(handle src, bool convert) {
    value = grip_python::Number<T>{};
    if (grip_python::complex_scalar(src)) {
      value.complex = true;
      return true;
    }
    make_caster<T> inner;
    if (!inner.load(src, convert)) return false;
    value.value = cast_op<T>(inner);
    return true;
  }

  static handle cast(const grip_python::Number<T>& x, return_value_policy policy, handle parent) {
    return make_caster<T>::cast(x.value, policy, parent);
  }
};

}  // namespace detail
}  // namespace pybind11
