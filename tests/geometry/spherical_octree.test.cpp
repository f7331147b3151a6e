// Sphere trees and spherical octrees: index arithmetic, containment, convergence, capacity.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include <grip/geometry/spherical_octree.hpp>

#include "support/allocation_counter.hpp"
#include "support/constants.hpp"
#include "support/random.hpp"

using grip_test::pi;

using namespace grip;

template class grip::SphereTree<double, 100, 8>;
template class grip::SphereTree<float, 20, 2>;
template class grip::SphericalOctree<double, 64>;
template class grip::SphericalOctree<float, 64>;

namespace {
constexpr int big_capacity = 32768;
template <class S>
SphericalOctree<S, big_capacity>& scratch_octree() {
  static SphericalOctree<S, big_capacity> t;  // 2-3 MB: static storage, not the stack
  return t;
}
template <class S>
Shape<S, 2> test_shape(int which) {
  const Matrix3<S> R = Eigen::AngleAxis<S>(S(0.5), Vector3<S>(S(1), S(-2), S(1)).normalized()).toRotationMatrix();
  Shape<S, 2> s;
  switch (which) {
    case 0: s.add(make_sphere<S>(S(0.04))); break;
    case 1: s.add(make_box<S>(Vector3<S>(S(0.05), S(0.03), S(0.02)), Vector3<S>(S(0.01), S(0), S(0)), R)); break;
    case 2: s.add(make_cylinder<S>(S(0.035), S(0.07), Vector3<S>::Zero(), R)); break;
    case 3: s.add(make_capsule<S>(S(0.02), S(0.03), Vector3<S>::Zero(), R)); break;
    default:
      s.add(make_box<S>(Vector3<S>(S(0.04), S(0.04), S(0.01))));
      s.add(make_cylinder<S>(S(0.01), S(0.03), Vector3<S>(S(0), S(0), S(0.03))));
  }
  return s;
}
}  // namespace

TEST_CASE("sphere tree: a complete 8-ary tree built breadth-first has the implicit indices") {
  SphereTree<double, 100, 8> t;
  CHECK(t.add_root(Vector3<double>::Zero(), 1.0) == 0);
  // Level 1: 8 children of the root, then 8 children of each of those (73 nodes).
  for (int i = 0; i < 9; ++i)
    for (int o = 0; o < 8; ++o) REQUIRE(t.add_child(i, Vector3<double>::Constant(i), 0.5) >= 0);
  CHECK(t.size() == 73);
  for (int i = 0; i < 9; ++i) {
    CHECK(t.node(i).first_child == 8 * i + 1);
    CHECK(t.node(i).child_count == 8);
  }
  for (int i = 1; i < 73; ++i) CHECK(t.node(i).parent == (i - 1) / 8);
  CHECK(t.node(72).level == 2);
  CHECK(t.leaf_count() == 64);
  // Refusals: a 9th child, a non-contiguous child, a bad parent, a full tree.
  CHECK(t.add_child(0, Vector3<double>::Zero(), 0.1) == -1);
  CHECK(t.add_child(3, Vector3<double>::Zero(), 0.1) == -1);  // node 3's children end at 32, size is 73
  CHECK(t.add_child(73, Vector3<double>::Zero(), 0.1) == -1);
  CHECK(t.add_child(-1, Vector3<double>::Zero(), 0.1) == -1);
  for (int i = 9; t.size() < 100; ++i) REQUIRE(t.add_child(i / 8 + 9, Vector3<double>::Zero(), 0.1) >= 0);
  CHECK(t.add_child(20, Vector3<double>::Zero(), 0.1) == -1);
  CHECK(t.size() == 100);
}

TEST_CASE_TEMPLATE("octree: contains every primitive and union, and keeps nothing far outside", S, double, float) {
  auto& oct = scratch_octree<S>();
  std::mt19937 rng(11);
  for (int which = 0; which < 5; ++which) {
    const Shape<S, 2> shape = test_shape<S>(which);
    const int depth = 5;
    REQUIRE(oct.build(shape, depth) == Status::Ok);
    CHECK(oct.depth() == depth);
    const S rho = std::sqrt(S(3)) * oct.cell_half_edge(depth);
    Vector3<S> lo, hi;
    shape.bounding_box(lo, hi);
    grip_test::Uniform u(0.0, 1.0);
    int inside = 0, far = 0;
    std::vector<int> hit;  // the distinct solid leaves found at points of the shape
    for (int t = 0; t < 1500; ++t) {
      const Vector3<S> p = lo + grip_test::draw3(rng, u).cast<S>().cwiseProduct(hi - lo) * S(1.2) - S(0.1) * (hi - lo);
      const S d = shape.distance(p);
      if (d <= S(0)) {  // a point of the shape lies in a kept leaf cell
        ++inside;
        const int leaf = oct.find_leaf(p);
        CHECK(leaf >= 0);
        if (leaf >= 0 && std::find(hit.begin(), hit.end(), leaf) == hit.end()) hit.push_back(leaf);
      } else if (d > S(2) * rho) {  // a kept leaf's points are within 2 rho of the shape
        ++far;
        CHECK(oct.find_leaf(p) == -1);
      }
    }
    CHECK(inside > 50);
    CHECK(far > 50);
    // Every leaf found is a solid leaf, so there are at least as many, and fewer than nodes.
    CHECK(oct.leaf_count() >= static_cast<int>(hit.size()));
    CHECK(oct.leaf_count() < oct.tree().size());
    for (const int leaf : hit) CHECK(oct.is_solid_leaf(leaf));
    // Structure: children contiguous and inside their parent's sphere; leaves carry a unit normal.
    bool contiguous = true, nested = true, unit = true, full_depth = true, empty_is_leaf = true;
    for (int i = 1; i < oct.tree().size(); ++i) {
      const SphereNode<S>& n = oct.tree().node(i);
      const SphereNode<S>& p = oct.tree().node(n.parent);
      contiguous = contiguous && i >= p.first_child && i < p.first_child + p.child_count;
      nested = nested && (n.center - p.center).norm() + n.radius <= p.radius * (S(1) + S(1e-5));
      unit = unit && std::abs(oct.plane(i).normal.norm() - S(1)) <= S(1e-4);
      if (oct.is_solid_leaf(i) && !oct.is_interior(i)) full_depth = full_depth && n.level == depth;
      if (oct.kind(i) == CellKind::Empty) empty_is_leaf = empty_is_leaf && oct.tree().is_leaf(i);
    }
    CHECK(contiguous);
    CHECK(nested);
    CHECK(unit);
    CHECK(full_depth);
    CHECK(empty_is_leaf);
  }
}

TEST_CASE_TEMPLATE("octree: leaf volume converges to the shape's volume from above", S, double, float) {
  // Every shape point lies in a leaf, so V_leaves >= V. A leaf cell meets the circumscribed
  // sphere test, so its points lie within 2 rho = 2 sqrt(3) h of the surface: V_leaves - V is
  // at most the shell of thickness 2 rho outside the surface, about area * 2 rho (+ curvature).
  auto& oct = scratch_octree<S>();
  for (int which : {0, 2}) {
    const Shape<S, 2> shape = test_shape<S>(which);
    const double V = double(shape.primitive(0).volume());
    const double area = which == 0 ? 4 * pi * 0.04 * 0.04 : 2 * pi * 0.035 * 0.14 + 2 * pi * 0.035 * 0.035;
    double prev_excess = 1e9;
    for (int depth = 2; depth <= 5; ++depth) {
      REQUIRE(oct.build(shape, depth) == Status::Ok);
      double vol = 0;
      for (int i = 0; i < oct.tree().size(); ++i)
        if (oct.is_solid_leaf(i)) vol += std::pow(2.0 * double(oct.cell_half_edge(oct.tree().node(i).level)), 3);
      const double excess = vol - V;
      const double rho = std::sqrt(3.0) * double(oct.cell_half_edge(depth));
      CHECK(excess >= -1e-6 * V);
      CHECK(excess <= area * 2 * rho * 1.5);
      CHECK(excess < prev_excess);
      prev_excess = excess;
    }
    CHECK(prev_excess < 0.5 * V);
  }
}

TEST_CASE_TEMPLATE("octree: capacity, bad input, and no heap at set-up", S, double, float) {
  static SphericalOctree<S, 64> small;
  const Shape<S, 2> shape = test_shape<S>(0);
  CHECK(small.build(shape, 3) == Status::InvalidInput);  // needs more than 64 cells
  CHECK(small.tree().empty());
  CHECK(small.required_capacity() > 64);
  CHECK(small.build(shape, 1) == Status::Ok);  // root + 8 octants
  CHECK(small.tree().size() == 9);
  CHECK(small.build(shape, -1) == Status::InvalidInput);
  CHECK(small.build(shape, max_octree_depth + 1) == Status::InvalidInput);
  CHECK(small.build(Shape<S, 2>{}, 2) == Status::InvalidInput);
  CHECK(small.find_leaf(Vector3<S>::Zero()) == -1);  // empty after failure
  auto& oct = scratch_octree<S>();
  grip_test::NoHeapScope scope;
  CHECK(oct.build(test_shape<S>(4), 4) == Status::Ok);
  CHECK(oct.find_leaf(Vector3<S>::Zero()) >= 0);
  CHECK(scope.allocations() == 0);
}
