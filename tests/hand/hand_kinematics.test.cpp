// Hand model: phalanx/joint layout, Buchholz dimensions, forward kinematics.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

#include <grip/hand/hand_joints.hpp>
#include <grip/hand/hand_kinematics.hpp>
#include <grip/hand/hand_model.hpp>

#include "support/allocation_counter.hpp"
#include "support/random.hpp"
#include "support/tolerance.hpp"

using namespace grip;

namespace {
template <class S>
using Iso = Eigen::Transform<S, 3, Eigen::Isometry>;
// Tolerances from round-off (support/tolerance.hpp), condition 1.
// A dimension c L (c a coefficient of Buchholz's table): c's and L's rounding to S, the product,
// and the reference's own product in double: k = 4 of the value.
template <class S>
double dim_tol(double value) {
  return grip_test::roundoff<S>(4, 1, value);
}
// A point of forward kinematics, on M (m), the hand length (every point lies within it of the
// wrist) plus |t| of a wrist shift: the base's rounding (3), per phalanx the rotation
// AngleAxis(sum, axis) * rest (about 8 roundings of 1, times a length) and p + l dir (2), over
// up to 3 phalanges (their lengths sum below L), then R p + t (6): k = 24.
template <class S>
double fk_tol(double M) {
  return grip_test::roundoff<S>(24, 1, M);
}
}  // namespace

template struct grip::HandDimensions<double>;
template struct grip::HandDimensions<float>;

TEST_CASE("phalanx and joint order: index <-> (finger, phalanx) round trip") {
  // The layout documented in hand_model.hpp, written out.
  const Finger f[14] = {Finger::Thumb, Finger::Thumb,  Finger::Index,  Finger::Index, Finger::Index,
                        Finger::Long,  Finger::Long,   Finger::Long,   Finger::Ring,  Finger::Ring,
                        Finger::Ring,  Finger::Little, Finger::Little, Finger::Little};
  const Phalanx p[14] = {Phalanx::Proximal, Phalanx::Distal,   Phalanx::Proximal, Phalanx::Middle,   Phalanx::Distal,
                         Phalanx::Proximal, Phalanx::Middle,   Phalanx::Distal,   Phalanx::Proximal, Phalanx::Middle,
                         Phalanx::Distal,   Phalanx::Proximal, Phalanx::Middle,   Phalanx::Distal};
  for (int k = 0; k < 14; ++k) {
    CHECK(phalanx_finger(k) == f[k]);
    CHECK(phalanx_kind(k) == p[k]);
    CHECK(phalanx_index(f[k], p[k]) == k);
  }
  CHECK(phalanx_index(Finger::Thumb, Phalanx::Middle) == -1);
  static_assert(hand_joint_count == 14 && hand_phalanx_count == 14, "the glove's 14 joints");
}

TEST_CASE_TEMPLATE("standard dimensions are Buchholz's fractions of hand length", S, double, float) {
  const S L = S(0.19);
  const HandDimensions<S> d = HandDimensions<S>::standard();
  CHECK(d.hand_length == L);
  REQUIRE(validate(d) == Status::Ok);
  // Buchholz et al. 1992 coefficients, typed from the paper's table (not from the code).
  CHECK(std::abs(double(d.length[static_cast<std::size_t>(phalanx_index(Finger::Long, Phalanx::Proximal))]) -
                 0.277 * 0.19) <= dim_tol<S>(0.277 * 0.19));
  CHECK(std::abs(double(d.length[static_cast<std::size_t>(phalanx_index(Finger::Index, Phalanx::Middle))]) -
                 0.143 * 0.19) <= dim_tol<S>(0.143 * 0.19));
  CHECK(std::abs(double(d.length[static_cast<std::size_t>(phalanx_index(Finger::Little, Phalanx::Distal))]) -
                 0.093 * 0.19) <= dim_tol<S>(0.093 * 0.19));
  CHECK(std::abs(double(d.length[static_cast<std::size_t>(phalanx_index(Finger::Thumb, Phalanx::Distal))]) -
                 0.158 * 0.19) <= dim_tol<S>(0.158 * 0.19));
  CHECK(std::abs(double(d.base[2].x()) - 0.373 * 0.19) <=
        dim_tol<S>(0.373 * 0.19));  // long MCP at its metacarpal length
  // Scaling: twice the hand, twice every length, radius and joint position.
  const HandDimensions<S> d2 = HandDimensions<S>::standard(S(2) * L);
  // Doubling is exact in binary, so c (2 L) and 2 (c L) round the same product: at most the
  // two evaluations' own roundings apart (k = 2 each, of the value; the thumb's base, a sum of
  // such terms, k = 8 of its norm).
  for (int k = 0; k < 14; ++k) {
    const double l2 = double(S(2) * d.length[static_cast<std::size_t>(k)]),
                 r2 = double(S(2) * d.radius[static_cast<std::size_t>(k)]);
    CHECK(std::abs(double(d2.length[static_cast<std::size_t>(k)]) - l2) <= grip_test::roundoff<S>(2, 1, l2));
    CHECK(std::abs(double(d2.radius[static_cast<std::size_t>(k)]) - r2) <= grip_test::roundoff<S>(2, 1, r2));
  }
  CHECK(double((d2.base[0] - S(2) * d.base[0]).norm()) <= grip_test::roundoff<S>(8, 1, double(d2.base[0].norm())));
  // Bad hand lengths give dimensions that validate() rejects.
  CHECK(validate(HandDimensions<S>::standard(S(0))) == Status::InvalidInput);
  CHECK(validate(HandDimensions<S>::standard(std::numeric_limits<S>::quiet_NaN())) == Status::InvalidInput);
  HandDimensions<S> bad = d;
  bad.flexion_axis[3] = Vector3<S>::UnitX();  // parallel to the rest direction
  CHECK(validate(bad) == Status::InvalidInput);
}

TEST_CASE_TEMPLATE("zero angles give the documented rest pose", S, double, float) {
  const HandDimensions<S> d = HandDimensions<S>::standard();
  const S L = d.hand_length;
  HandPosture<S> h;
  REQUIRE(forward_kinematics(d, Iso<S>::Identity(), JointAngles<S>::Zero(), h) == Status::Ok);
  // Fingers: straight along +x from the MCP at (metacarpal fraction * L, y, 0).
  const double rest_tol = grip_test::roundoff<S>(12, 1, 0.19);
  const double mc[5] = {0, 0.374, 0.373, 0.336, 0.295};
  const double y[5] = {0, 0.105, 0, -0.10, -0.20};
  for (int f = 1; f < 5; ++f) {
    double x = mc[f] * 0.19;
    for (int p = 0; p < 3; ++p) {
      const PhalanxCapsule<S>& c =
          h.phalanges[static_cast<std::size_t>(phalanx_index(static_cast<Finger>(f), static_cast<Phalanx>(p)))];
      CHECK(c.finger == static_cast<Finger>(f));
      CHECK(c.phalanx == static_cast<Phalanx>(p));
      // Forward kinematics' points at zero angles: AngleAxis(0) is the identity exactly, and so
      // is the wrist, so fk_tol's count shrinks to the base's 3 roundings and p + l dir's 2 per
      // phalanx (9), and the reference x's differences in S, 1 per phalanx: k = 12 of L.
      CHECK(std::abs(double(c.base.x()) - x) <= rest_tol);
      CHECK(std::abs(double(c.base.y()) - y[f] * 0.19) <= rest_tol);
      CHECK(double(std::abs(c.base.z())) <= rest_tol);
      CHECK(double(std::abs(c.tip.y() - c.base.y())) <= rest_tol);
      CHECK(double(std::abs(c.tip.z())) <= rest_tol);
      x += double(c.tip.x() - c.base.x());
    }
    // Long finger: MCP + proximal + middle + distal = (0.373 + 0.277 + 0.170 + 0.108) L.
    if (f == 2) CHECK(std::abs(x - 0.928 * 0.19) <= rest_tol);
  }
  // Thumb: from its MCP = CMC (0.05 L, 0.22 L, 0) + 0.251 L u, along u = (sin 25, 0, -cos 25).
  const double b = 25.0 * 3.141592653589793 / 180.0;
  const Vector3<double> u(std::sin(b), 0, -std::cos(b));
  const Vector3<double> mcp = Vector3<double>(0.05 * 0.19, 0.22 * 0.19, 0) + 0.251 * 0.19 * u;
  const Vector3<double> tip = mcp + (0.196 + 0.158) * 0.19 * u;
  CHECK((h.phalanges[0].base.template cast<double>() - mcp).norm() <= rest_tol);
  CHECK((h.phalanges[1].tip.template cast<double>() - tip).norm() <= rest_tol);
  CHECK(std::abs(double(h.phalanges[0].radius) - 0.050 * 0.19) <= dim_tol<S>(0.050 * 0.19));
  (void)L;
}

TEST_CASE_TEMPLATE("flexion: a right-angle MCP turns the finger palmar, the wrist pose moves everything", S, double,
                   float) {
  const HandDimensions<S> d = HandDimensions<S>::standard();
  JointAngles<S> q = JointAngles<S>::Zero();
  const int k = phalanx_index(Finger::Index, Phalanx::Proximal);
  q(k) = S(3.14159265358979323846 / 2);
  q(k + 1) = S(3.14159265358979323846 / 2);  // PIP: the middle phalanx then points back, -x
  HandPosture<S> h;
  REQUIRE(forward_kinematics(d, Iso<S>::Identity(), q, h) == Status::Ok);
  // Proximal: rotating +x by 90 deg about +y gives -z (palmar).
  const Vector3<S> prox = h.phalanges[static_cast<std::size_t>(k)].tip - h.phalanges[static_cast<std::size_t>(k)].base;
  // A difference of two FK points (2 fk_tol), and the angle's own rounding to S (pi/2 within
  // u pi/2; the PIP's sum pi within u pi) times the length, below u L: k = 2 x 24 + 1.
  CHECK(double((prox - d.length[static_cast<std::size_t>(k)] * Vector3<S>(0, 0, -1)).norm()) <=
        grip_test::roundoff<S>(49, 1, 0.19));
  const Vector3<S> mid =
      h.phalanges[static_cast<std::size_t>(k + 1)].tip - h.phalanges[static_cast<std::size_t>(k + 1)].base;
  CHECK(double((mid - d.length[static_cast<std::size_t>(k + 1)] * Vector3<S>(-1, 0, 0)).norm()) <=
        grip_test::roundoff<S>(49, 1, 0.19));
  // Chained: the next base is R p + t of the same p as this tip: equal, at most one
  // evaluation's last roundings apart (k = 2 of L).
  CHECK(double((h.phalanges[static_cast<std::size_t>(k + 1)].base - h.phalanges[static_cast<std::size_t>(k)].tip)
                   .norm()) <= grip_test::roundoff<S>(2, 1, 0.19));

  // A wrist pose T: every point is T applied to the identity-pose point.
  Iso<S> T = Iso<S>::Identity();
  T.linear() = Eigen::AngleAxis<S>(S(0.7), Vector3<S>(S(1), S(2), S(-1)).normalized()).toRotationMatrix();
  T.translation() = Vector3<S>(S(0.3), S(-0.1), S(1.2));
  HandPosture<S> g;
  REQUIRE(forward_kinematics(d, T, q, g) == Status::Ok);
  // Both evaluate R p + t of the same p (h's identity pose is exact): the two evaluations' 6
  // roundings each of |p| + |t| (k = 12), on M = L + |t| (support/tolerance.hpp).
  const double M = 0.19 + double(T.translation().norm());
  for (int i = 0; i < 14; ++i) {
    CHECK(double((g.phalanges[static_cast<std::size_t>(i)].base - T * h.phalanges[static_cast<std::size_t>(i)].base)
                     .norm()) <= grip_test::roundoff<S>(12, 1, M));
    CHECK(double((g.phalanges[static_cast<std::size_t>(i)].tip - T * h.phalanges[static_cast<std::size_t>(i)].tip)
                     .norm()) <= grip_test::roundoff<S>(12, 1, M));
  }
}

TEST_CASE_TEMPLATE("forward kinematics rejects bad input and does not allocate", S, double, float) {
  const HandDimensions<S> d = HandDimensions<S>::standard();
  HandPosture<S> h;
  JointAngles<S> q = JointAngles<S>::Constant(S(0.3));
  {
    grip_test::NoHeapScope scope;
    CHECK(forward_kinematics(d, Iso<S>::Identity(), q, h) == Status::Ok);
    CHECK(scope.allocations() == 0);
  }
  const HandPosture<S> before = h;
  q(5) = std::numeric_limits<S>::quiet_NaN();
  CHECK(forward_kinematics(d, Iso<S>::Identity(), q, h) == Status::InvalidInput);
  q(5) = S(0);
  Iso<S> scaled = Iso<S>::Identity();
  scaled.linear() *= S(2);  // not a rotation
  CHECK(forward_kinematics(d, scaled, q, h) == Status::InvalidInput);
  Iso<S> inf = Iso<S>::Identity();
  inf.translation().x() = std::numeric_limits<S>::infinity();
  CHECK(forward_kinematics(d, inf, q, h) == Status::InvalidInput);
  HandDimensions<S> bad = d;
  bad.radius[7] = S(-1);
  CHECK(forward_kinematics(bad, Iso<S>::Identity(), q, h) == Status::InvalidInput);
  CHECK(h.phalanges[3].tip == before.phalanges[3].tip);  // unchanged on failure
}

// ---- The whole hand: 20 joints, both hands. -----------------------------------------------------

TEST_CASE_TEMPLATE("20 joints at zero: the open hand, every phalanx in or above the palm plane", S, double, float) {
  const HandDimensions<S> d = HandDimensions<S>::standard();
  HandPosture<S> open, paper;
  REQUIRE(forward_kinematics(d, Iso<S>::Identity(), HandJoints<S>::Zero(), open) == Status::Ok);
  REQUIRE(forward_kinematics(d, Iso<S>::Identity(), JointAngles<S>::Zero(), paper) == Status::Ok);
  const double tol = grip_test::roundoff<S>(24, 1, 0.19);
  for (std::size_t k = 0; k < 14; ++k) {
    CHECK(double(open.phalanges[k].base.z()) >= -tol);
    CHECK(double(open.phalanges[k].tip.z()) >= -tol);
    if (k >= 2) {  // the fingers are the paper hand's
      CHECK(double((open.phalanges[k].tip - paper.phalanges[k].tip).norm()) <= tol);
    }
  }
  // The paper hand's thumb hangs below the palm (what the whole hand fixes).
  CHECK(double(paper.phalanges[1].tip.z()) < -0.05);
  // The open thumb: from the CMC (0.05 L, 0.22 L, 0) along (cos 40, sin 40, 0), metacarpal
  // 0.251 L, phalanges 0.196 L and 0.158 L (Buchholz's fractions).
  const double a = 40.0 * 3.141592653589793 / 180.0;
  const Vector3<double> u(std::cos(a), std::sin(a), 0);
  const Vector3<double> cmc(0.05 * 0.19, 0.22 * 0.19, 0);
  CHECK((open.phalanges[0].base.template cast<double>() - (cmc + 0.251 * 0.19 * u)).norm() <= tol);
  CHECK((open.phalanges[1].tip.template cast<double>() - (cmc + (0.251 + 0.196 + 0.158) * 0.19 * u)).norm() <= tol);
  // The joint frames: each phalanx's base is its own joint's point; the paper hand's CMC and
  // abductions are fixed (zero axes), the whole hand's are unit.
  for (int k = 0; k < 14; ++k)
    CHECK(double((open.joints[detail::idx(phalanx_joint(k))].point - open.phalanges[detail::idx(k)].base).norm()) <=
          tol);
  for (int i : {0, 1, 4, 8, 12, 16}) {
    CHECK(paper.joints[detail::idx(i)].axis.norm() == S(0));
    CHECK(std::abs(double(open.joints[detail::idx(i)].axis.norm()) - 1) <= tol);
  }
  // The CMC axes are not perpendicular: 80 degrees apart.
  CHECK(std::abs(double(open.joints[0].axis.dot(open.joints[1].axis)) - std::cos(80.0 * 3.141592653589793 / 180.0)) <=
        1e3 * tol);
}

TEST_CASE_TEMPLATE("20 joints: abduction turns a finger about the palm normal, the thumb opposes", S, double, float) {
  const HandDimensions<S> d = HandDimensions<S>::standard();
  HandJoints<S> q = HandJoints<S>::Zero();
  q(5) = S(0.4);  // index MCP, PIP, DIP flexed
  q(6) = S(0.5);
  q(7) = S(0.3);
  HandPosture<S> bent, spread;
  REQUIRE(forward_kinematics(d, Iso<S>::Identity(), q, bent) == Status::Ok);
  q(4) = S(0.25);  // then abducted 0.25 rad radially
  REQUIRE(forward_kinematics(d, Iso<S>::Identity(), q, spread) == Status::Ok);
  // Every index point is the bent one turned by 0.25 about +z through the MCP (computed here
  // with a rotation of the test's own).
  const Vector3<double> mcp = d.base[1].template cast<double>();
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(0.25, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double tol = grip_test::roundoff<S>(64, 1, 0.19);
  for (std::size_t k = 2; k < 5; ++k) {
    const Vector3<double> want = mcp + Rz * (bent.phalanges[k].tip.template cast<double>() - mcp);
    CHECK((spread.phalanges[k].tip.template cast<double>() - want).norm() <= tol);
  }
  CHECK(double(spread.phalanges[4].tip.y()) > double(bent.phalanges[4].tip.y()) + 0.01);  // radial
  // Thumb CMC flexion carries the thumb ulnarly (-y), abduction palmarly (-z).
  HandJoints<S> t = HandJoints<S>::Zero();
  HandPosture<S> open, flexed, abducted;
  REQUIRE(forward_kinematics(d, Iso<S>::Identity(), t, open) == Status::Ok);
  t(0) = S(0.5);
  REQUIRE(forward_kinematics(d, Iso<S>::Identity(), t, flexed) == Status::Ok);
  t(0) = S(0);
  t(1) = S(0.5);
  REQUIRE(forward_kinematics(d, Iso<S>::Identity(), t, abducted) == Status::Ok);
  CHECK(double(flexed.phalanges[1].tip.y()) < double(open.phalanges[1].tip.y()) - 0.02);
  CHECK(double(abducted.phalanges[1].tip.z()) < -0.02);
  // Thumb MCP and IP flexion at the open pose move the tip ulnarly and palmarly.
  t(1) = S(0);
  t(2) = S(0.3);
  t(3) = S(0.3);
  HandPosture<S> curled;
  REQUIRE(forward_kinematics(d, Iso<S>::Identity(), t, curled) == Status::Ok);
  CHECK(double(curled.phalanges[1].tip.y()) < double(open.phalanges[1].tip.y()));
  CHECK(double(curled.phalanges[1].tip.z()) < 0);
}

TEST_CASE_TEMPLATE("the left hand is the right hand's mirror image at every posture", S, double, float) {
  const HandDimensions<S> right = HandDimensions<S>::standard();
  const HandDimensions<S> left = HandDimensions<S>::standard(S(0.19), Side::Left);
  CHECK(left.side == Side::Left);
  REQUIRE(validate(left) == Status::Ok);
  std::mt19937 g(77);
  const grip_test::Uniform u(0, 1);
  const JointLimits<S> l = right.limits;
  for (int trial = 0; trial < 20; ++trial) {
    HandJoints<S> q;
    for (int i = 0; i < 20; ++i) {
      const double t = u(g);
      q(i) = S((1 - t) * double(l.lower[detail::idx(i)]) + t * double(l.upper[detail::idx(i)]));
    }
    HandPosture<S> r, m;
    REQUIRE(forward_kinematics(right, Iso<S>::Identity(), q, r) == Status::Ok);
    REQUIRE(forward_kinematics(left, Iso<S>::Identity(), q, m) == Status::Ok);
    const Eigen::DiagonalMatrix<S, 3> M(S(1), S(-1), S(1));
    const double tol = grip_test::roundoff<S>(64, 1, 0.19);
    for (std::size_t k = 0; k < 14; ++k) {
      CHECK(double((m.phalanges[k].base - M * r.phalanges[k].base).norm()) <= tol);
      CHECK(double((m.phalanges[k].tip - M * r.phalanges[k].tip).norm()) <= tol);
    }
    for (std::size_t i = 0; i < 20; ++i)  // axes mirror as axes: -M a
      CHECK(double((m.joints[i].axis + (M * r.joints[i].axis)).norm()) <= tol);
  }
}
