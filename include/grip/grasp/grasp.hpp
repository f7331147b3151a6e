#pragma once
/// \file
/// A grasp: a set of contacts on one object, with its grasp matrix G and the KKT
/// system (H, b) of the paper's eq. 9.

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#include "grip/contact/contact.hpp"
#include "grip/contact/contact_model.hpp"
#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// A set of contacts of one contact Model on one object.
///
/// - `N`: contact count fixed at compile time, or `Dynamic` for a run-time count of at
///   most `MaxN` (contacts come and go frame to frame). No heap in either case: storage
///   for `capacity` contacts lives inside the object.
/// - `Model`: FrictionlessPoint, HardFinger (default, the paper's) or SoftFinger.
///
/// Invariants: every stored contact satisfies validate(), its normal unit to 4 eps (a normal
/// given within ScalarTraits::normal_tolerance of unit is stored scaled to unit length, one
/// unit to round-off as given); `size() <= capacity`;
/// inverse_weight(i) == 1 / contact(i).weight for every set slot.
/// With a fixed N the grasp is `complete()` once each of the N slots has been set;
/// solvers answer InvalidInput for an incomplete grasp.
template <int N, class Model = HardFinger, class Scalar = double, int MaxN = N>
class Grasp {
  static_assert(N == Dynamic || (N >= 1 && MaxN == N), "fixed N needs MaxN == N");
  static_assert(N != Dynamic || MaxN >= 1, "a Dynamic grasp needs a compile-time bound MaxN >= 1");

 public:
  using ScalarType = Scalar;                                ///< the scalar type (float or double).
  using ModelType = Model;                                  ///< the contact model policy.
  static constexpr int fixed_size = N;                      ///< N (or Dynamic).
  static constexpr int capacity = N == Dynamic ? MaxN : N;  ///< most contacts held.
  static constexpr int dim = Model::dim;                    ///< unknowns per contact.
  /// Unknowns N * dim, or Dynamic for a Dynamic grasp (the Eigen size of ForceVector).
  static constexpr int unknowns_at_compile_time = times_or_dynamic(N, dim);
  /// Most unknowns, capacity * dim: the storage bound of ForceVector and GraspMatrix.
  static constexpr int max_unknowns = capacity * dim;
  /// KKT size 6 + N * dim, or Dynamic (the Eigen size of KktMatrix and KktVector).
  static constexpr int kkt_size_at_compile_time = plus_or_dynamic(6, unknowns_at_compile_time);
  /// Largest KKT size, 6 + max_unknowns: the storage bound of KktMatrix and KktVector.
  static constexpr int max_kkt_size = 6 + max_unknowns;
  /// Stacked contact unknowns x = (x_1, ..., x_n): size() * dim.
  using ForceVector = Eigen::Matrix<Scalar, unknowns_at_compile_time, 1, Eigen::ColMajor, max_unknowns, 1>;
  /// Grasp matrix G: 6 x (size() * dim).
  using GraspMatrix = Eigen::Matrix<Scalar, 6, unknowns_at_compile_time, Eigen::ColMajor, 6, max_unknowns>;
  /// KKT matrix H of eq. 9: (6 + size() * dim) square.
  using KktMatrix = Eigen::Matrix<Scalar, kkt_size_at_compile_time, kkt_size_at_compile_time, Eigen::ColMajor,
                                  max_kkt_size, max_kkt_size>;
  /// KKT right-hand side b and unknown c = (f, lambda) of eq. 9.
  using KktVector = Eigen::Matrix<Scalar, kkt_size_at_compile_time, 1, Eigen::ColMajor, max_kkt_size, 1>;
  /// One contact's unknowns.
  using ContactVector = Eigen::Matrix<Scalar, dim, 1>;
  /// One contact.
  using ContactType = Contact<Scalar>;
  Grasp() = default;

  /// Appends a contact. InvalidInput if the contact breaks an invariant of Contact or the
  /// grasp already holds `capacity` contacts (always, for a fixed N: its N slots exist from
  /// the start; use set()); the grasp is then unchanged.
  Status add(const ContactType& c) {
    const int n = count_;  // a local bound check the optimiser can see through (-Warray-bounds)
    if (n < 0 || n >= capacity) return Status::InvalidInput;
    if (validate(c) != Status::Ok) return Status::InvalidInput;
    const auto k = detail::idx(n);
    store(k, c);
    is_set_[k] = true;
    count_ = n + 1;
    ++set_count_;
    return Status::Ok;
  }

  /// Replaces contact i (0 <= i < size()). InvalidInput for a bad index or contact; the
  /// grasp is then unchanged.
  Status set(int i, const ContactType& c) {
    if (i < 0 || i >= size() || i >= capacity) return Status::InvalidInput;  // size() <= capacity; the
    if (validate(c) != Status::Ok) return Status::InvalidInput;              // bound is for -Warray-bounds
    const auto k = detail::idx(i);
    store(k, c);
    if (!is_set_[k]) {
      is_set_[k] = true;
      ++set_count_;
    }
    return Status::Ok;
  }

  /// Removes every contact (Dynamic), or marks every slot unset (fixed N).
  void clear() {
    if constexpr (N == Dynamic) count_ = 0;
    is_set_.fill(false);
    set_count_ = 0;
  }

  /// Number of contacts n: N for a fixed grasp, the number added for a Dynamic one.
  int size() const { return count_; }
  /// Number of unknowns, size() * dim.
  int unknowns() const { return count_ * dim; }
  /// True when every one of the size() contacts has been set (always, for Dynamic).
  bool complete() const { return set_count_ == count_; }
  /// Contact i. Precondition (GRIP_ASSERT, as Eigen's operator() has eigen_assert): 0 <= i < size().
  const ContactType& contact(int i) const {
    GRIP_ASSERT(i < count_);
    return contacts_[detail::idx(i)];
  }
  /// 1 / contact(i).weight, kept when the contact is stored so that solvers multiply instead
  /// of dividing per contact and frame (0 for a slot never set). Precondition (GRIP_ASSERT):
  /// 0 <= i < size().
  Scalar inverse_weight(int i) const {
    GRIP_ASSERT(i < count_);
    return inverse_weights_[detail::idx(i)];
  }
  /// The size() contacts as one array, contacts()[i] == contact(i): what a vectorised pass reads
  /// (contact/coulomb_kernel.hpp reads each normal and friction in place). Valid while the grasp
  /// lives; entries of slots never set are default contacts.
  const ContactType* contacts() const { return contacts_.data(); }

  /// The grasp matrix G (6 x n*dim): column block i is Model::basis(contact(i)).
  /// For HardFinger this is eq. 3: G = [I3 ... I3; R_1 ... R_n].
  GraspMatrix grasp_matrix() const {
    GraspMatrix g(6, unknowns());
    for (int i = 0; i < count_; ++i) g.template middleCols<dim>(i * dim) = Model::basis(contact(i));
    return g;
  }

  /// The stacked targets t = (t_1, ..., t_n) of F2 (eq. 7): s_i a_i for a hard finger.
  ForceVector target() const {
    ForceVector t(unknowns());
    for (int i = 0; i < count_; ++i) t.template segment<dim>(i * dim) = Model::target(contact(i));
    return t;
  }

  /// The paper's H of eq. 9, in exactly its block layout, unknowns c = (f, lambda):
  ///     H = [ G    0_6x6 ]   rows 0..5: equilibrium G f = w_e
  ///         [ W    -G^T  ]   rows 6.. : stationarity W f - G^T lambda = W t
  /// The paper's lower-left block is I_(3n); with weights it is W = diag(w_i I_dim), which
  /// equals I when all weights are 1 (the paper's F2). The lower-right block -G^T has the
  /// rows [-I3  R_i] of eq. 9 for a hard finger (since -R_i^T = R_i).
  KktMatrix kkt_matrix() const {
    const int m = unknowns();
    KktMatrix h = KktMatrix::Zero(6 + m, 6 + m);
    const GraspMatrix g = grasp_matrix();
    h.topLeftCorner(6, m) = g;
    h.bottomRightCorner(m, 6) = -g.transpose();
    for (int i = 0; i < count_; ++i) h.block(6 + i * dim, i * dim, dim, dim).diagonal().setConstant(contact(i).weight);
    return h;
  }

  /// The paper's b of eq. 9: (w_e; W t) with w_e = -w_ext (so b = (-F_ext, -N_ext, s_1 a_1, ...)
  /// for unit weights). `w_ext` is the external wrench on the object.
  KktVector kkt_rhs(const Wrench<Scalar>& w_ext) const {
    KktVector b(6 + unknowns());
    b.template head<6>() = -w_ext;
    for (int i = 0; i < count_; ++i)
      b.template segment<dim>(6 + i * dim) = contact(i).weight * Model::target(contact(i));
    return b;
  }

  /// The wrench G x that the contact unknowns x apply on the object.
  template <class Derived>
  Wrench<Scalar> wrench(const Eigen::MatrixBase<Derived>& x) const {
    Wrench<Scalar> w = Wrench<Scalar>::Zero();
    for (int i = 0; i < count_; ++i) w += Model::wrench(contact(i), ContactVector(x.template segment<dim>(i * dim)));
    return w;
  }

 private:
  /// Stores contact c in slot k with the data derived from it.
  void store(std::size_t k, const ContactType& c) {
    contacts_[k] = c;
    // The cones need a unit axis: their projections of a large v near the polar cone err by
    // |v| ||a|^2 - 1|, far more than the small result's round-off. A normal that validate()
    // accepted but that is not unit to round-off is scaled to unit length; unit ones are kept
    // bit for bit.
    Vector3<Scalar>& a = contacts_[k].normal;
    const Scalar a2 = a.squaredNorm();
    if (std::abs(a2 - Scalar(1)) > Scalar(8) * std::numeric_limits<Scalar>::epsilon()) a /= std::sqrt(a2);
    inverse_weights_[k] = Scalar(1) / c.weight;
  }

  std::array<ContactType, detail::idx(capacity)> contacts_{};
  std::array<Scalar, detail::idx(capacity)> inverse_weights_{};
  std::array<bool, detail::idx(capacity)> is_set_{};
  int count_{N == Dynamic ? 0 : N};
  int set_count_{0};
};

/// True for any Grasp<...> type.
template <class T>
struct is_grasp : std::false_type {};
template <int N, class M, class S, int MaxN>
struct is_grasp<Grasp<N, M, S, MaxN>> : std::true_type {};

}  // namespace grip
