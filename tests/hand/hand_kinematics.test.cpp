// Hand model: phalanx/joint layout, Buchholz dimensions, forward kinematics.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <grip/hand/hand_kinematics.hpp>
#include <grip/hand/hand_model.hpp>

#include "support/allocation_counter.hpp"

using namespace grip;

namespace {
template <class S>
using Iso = Eigen::Transform<S, 3, Eigen::Isometry>;
template <class S>
S tol() {
  return std::is_same<S, float>::value ? S(1e-5) : S(1e-12);
}
}  // namespace

template struct grip::HandDimensions<double>;
template struct grip::HandDimensions<float>;

TEST_CASE("phalanx and joint order: index <-> (finger, phalanx) round trip") {
  // The layout documented in hand_model.hpp, written out.
  const Finger f[14] = {Finger::Thumb, Finger::Thumb, Finger::Index, Finger::Index, Finger::Index,
                        Finger::Long,  Finger::Long,  Finger::Long,  Finger::Ring,  Finger::Ring,
                        Finger::Ring,  Finger::Little, Finger::Little, Finger::Little};
  const Phalanx p[14] = {Phalanx::Proximal, Phalanx::Distal, Phalanx::Proximal, Phalanx::Middle, Phalanx::Distal,
                         Phalanx::Proximal, Phalanx::Middle, Phalanx::Distal,   Phalanx::Proximal, Phalanx::Middle,
                         Phalanx::Distal,   Phalanx::Proximal, Phalanx::Middle, Phalanx::Distal};
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
  CHECK(d.length[static_cast<std::size_t>(phalanx_index(Finger::Long, Phalanx::Proximal))] == doctest::Approx(0.277 * 0.19));
  CHECK(d.length[static_cast<std::size_t>(phalanx_index(Finger::Index, Phalanx::Middle))] == doctest::Approx(0.143 * 0.19));
  CHECK(d.length[static_cast<std::size_t>(phalanx_index(Finger::Little, Phalanx::Distal))] == doctest::Approx(0.093 * 0.19));
  CHECK(d.length[static_cast<std::size_t>(phalanx_index(Finger::Thumb, Phalanx::Distal))] == doctest::Approx(0.158 * 0.19));
  CHECK(d.base[2].x() == doctest::Approx(0.373 * 0.19));  // long MCP at its metacarpal length
  // Scaling: twice the hand, twice every length, radius and joint position.
  const HandDimensions<S> d2 = HandDimensions<S>::standard(S(2) * L);
  for (int k = 0; k < 14; ++k) {
    CHECK(d2.length[static_cast<std::size_t>(k)] == doctest::Approx(double(S(2) * d.length[static_cast<std::size_t>(k)])).epsilon(1e-5));
    CHECK(d2.radius[static_cast<std::size_t>(k)] == doctest::Approx(double(S(2) * d.radius[static_cast<std::size_t>(k)])).epsilon(1e-5));
  }
  CHECK((d2.base[0] - S(2) * d.base[0]).norm() <= S(10) * tol<S>());
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
  const double mc[5] = {0, 0.374, 0.373, 0.336, 0.295};
  const double y[5] = {0, 0.105, 0, -0.10, -0.20};
  for (int f = 1; f < 5; ++f) {
    double x = mc[f] * 0.19;
    for (int p = 0; p < 3; ++p) {
      const PhalanxCapsule<S>& c = h.phalanges[static_cast<std::size_t>(phalanx_index(static_cast<Finger>(f), static_cast<Phalanx>(p)))];
      CHECK(c.finger == static_cast<Finger>(f));
      CHECK(c.phalanx == static_cast<Phalanx>(p));
      CHECK(double(c.base.x()) == doctest::Approx(x).epsilon(1e-5));
      CHECK(double(c.base.y()) == doctest::Approx(y[f] * 0.19).epsilon(1e-5));
      CHECK(std::abs(c.base.z()) <= tol<S>());
      CHECK(std::abs(c.tip.y() - c.base.y()) <= tol<S>());
      CHECK(std::abs(c.tip.z()) <= tol<S>());
      x += double(c.tip.x() - c.base.x());
    }
    // Long finger: MCP + proximal + middle + distal = (0.373 + 0.277 + 0.170 + 0.108) L.
    if (f == 2) CHECK(x == doctest::Approx(0.928 * 0.19).epsilon(1e-5));
  }
  // Thumb: from its MCP = CMC (0.05 L, 0.22 L, 0) + 0.251 L u, along u = (sin 25, 0, -cos 25).
  const double b = 25.0 * 3.141592653589793 / 180.0;
  const Vector3<double> u(std::sin(b), 0, -std::cos(b));
  const Vector3<double> mcp = Vector3<double>(0.05 * 0.19, 0.22 * 0.19, 0) + 0.251 * 0.19 * u;
  const Vector3<double> tip = mcp + (0.196 + 0.158) * 0.19 * u;
  CHECK((h.phalanges[0].base.template cast<double>() - mcp).norm() <= 1e-6);
  CHECK((h.phalanges[1].tip.template cast<double>() - tip).norm() <= 1e-6);
  CHECK(h.phalanges[0].radius == doctest::Approx(0.050 * 0.19));
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
  CHECK((prox - d.length[static_cast<std::size_t>(k)] * Vector3<S>(0, 0, -1)).norm() <= S(10) * tol<S>());
  const Vector3<S> mid = h.phalanges[static_cast<std::size_t>(k + 1)].tip - h.phalanges[static_cast<std::size_t>(k + 1)].base;
  CHECK((mid - d.length[static_cast<std::size_t>(k + 1)] * Vector3<S>(-1, 0, 0)).norm() <= S(10) * tol<S>());
  CHECK((h.phalanges[static_cast<std::size_t>(k + 1)].base - h.phalanges[static_cast<std::size_t>(k)].tip).norm() <= tol<S>());  // chained

  // A wrist pose T: every point is T applied to the identity-pose point.
  Iso<S> T = Iso<S>::Identity();
  T.linear() = Eigen::AngleAxis<S>(S(0.7), Vector3<S>(S(1), S(2), S(-1)).normalized()).toRotationMatrix();
  T.translation() = Vector3<S>(S(0.3), S(-0.1), S(1.2));
  HandPosture<S> g;
  REQUIRE(forward_kinematics(d, T, q, g) == Status::Ok);
  for (int i = 0; i < 14; ++i) {
    CHECK((g.phalanges[static_cast<std::size_t>(i)].base - T * h.phalanges[static_cast<std::size_t>(i)].base).norm() <= S(100) * tol<S>());
    CHECK((g.phalanges[static_cast<std::size_t>(i)].tip - T * h.phalanges[static_cast<std::size_t>(i)].tip).norm() <= S(100) * tol<S>());
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
