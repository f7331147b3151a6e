// core/assert.hpp and core/index.hpp as this build has them (asserts on in the suite's debug and
// test builds, off under NDEBUG): a failing GRIP_ASSERT calls the installed handler with the
// condition, file and line; the unchecked accessors check their index; detail::idx converts.
// The switch itself (GRIP_DISABLE_ASSERTS, GRIP_ENABLE_ASSERTS, NDEBUG) is tested in
// assert_switch.test.cpp.
#include <doctest/doctest.h>

#include <cstring>

#include <grip/core/assert.hpp>
#include <grip/core/index.hpp>
#include <grip/collision/hand_contact.hpp>
#include <grip/geometry/shape.hpp>
#include <grip/geometry/sphere_tree.hpp>
#include <grip/geometry/triangle_mesh.hpp>
#include <grip/grasp/grasp.hpp>
#include <grip/monitor/grasp_state.hpp>

#include "support/fixtures.hpp"

namespace assert_test {

using namespace grip;

// What the recording handler saw. A handler is a plain function pointer: no captures, no heap.
int g_failures = 0;
const char* g_condition = nullptr;
const char* g_file = nullptr;
int g_line = 0;

void record(const char* condition, const char* file, int line) {
  ++g_failures;
  g_condition = condition;
  g_file = file;
  g_line = line;
}

/// Installs the recording handler for its lifetime, then puts back the one before.
struct Recorder {
  AssertHandler previous;
  Recorder() : previous(set_assert_handler(&record)) {
    g_failures = 0;
    g_condition = g_file = nullptr;
    g_line = 0;
  }
  ~Recorder() { set_assert_handler(previous); }
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;
};

/// How many failures one call that breaks a precondition reports in this build.
constexpr int expected = GRIP_ASSERTS_ENABLED ? 1 : 0;

TEST_CASE("GRIP_ASSERT: a false condition calls the handler with its text, file and line") {
  Recorder r;
  int evaluations = 0;
  GRIP_ASSERT(++evaluations > 0);
  CHECK(g_failures == 0);
  const int line = __LINE__ + 1;
  GRIP_ASSERT(evaluations < 0);
  CHECK(evaluations == (GRIP_ASSERTS_ENABLED ? 1 : 0));  // on: evaluated once; off: never
  REQUIRE(g_failures == expected);
  if (GRIP_ASSERTS_ENABLED) {
    CHECK(std::strcmp(g_condition, "evaluations < 0") == 0);
    CHECK(std::strstr(g_file, "assert.test.cpp") != nullptr);
    CHECK(g_line == line);
  }
}

TEST_CASE("set_assert_handler returns the handler it replaces, nullptr the default") {
  const AssertHandler before = set_assert_handler(&record);
  // (Doubled parentheses: doctest cannot print a function pointer.)
  CHECK((before == nullptr));  // the suite runs with the default handler
  CHECK((set_assert_handler(nullptr) == &record));
  CHECK((set_assert_handler(before) == nullptr));
}

TEST_CASE("GRIP_DETAIL_ASSERT_OFF, the compiled-out form, never evaluates its condition") {
  Recorder r;
  int evaluations = 0;
  GRIP_DETAIL_ASSERT_OFF(++evaluations < 0);
  CHECK(evaluations == 0);
  CHECK(g_failures == 0);
  GRIP_DETAIL_ASSERT_ON(++evaluations < 0);  // the checking form, whatever the build's switch
  CHECK(evaluations == 1);
  CHECK(g_failures == 1);
}

TEST_CASE("detail::idx: the std::size_t of a non-negative index, in constant expressions too") {
  static_assert(detail::idx(0) == 0u, "");
  static_assert(detail::idx(7) == 7u, "");
  static_assert(detail::idx(7L) == 7u, "");
  static_assert(detail::idx(Finger::Ring) == 3u, "");
  static_assert(sizeof(std::array<int, detail::idx(5)>) == 5 * sizeof(int), "");
  Recorder r;
  CHECK(detail::idx(41) == std::size_t(41));
  CHECK(g_failures == 0);
#if GRIP_ASSERTS_ENABLED
  // The recorder returns, so the broken precondition goes on: to 0, not to 2^64 - 1.
  CHECK(detail::idx(-1) == 0u);
  CHECK(detail::idx(-5L) == 0u);
  CHECK(g_failures == 2);
#endif  // with asserts off a negative index is undefined behaviour: nothing to call
}

// Each accessor is called one past its size but inside its storage: the handler returns, and the
// accessor reads a slot that exists (no undefined behaviour for the sanitizers to catch).
TEST_CASE("The unchecked accessors assert their index: Grasp, GraspModes, HandContacts") {
  Recorder r;
  Grasp<Dynamic, HardFinger, double, 4> g;
  REQUIRE(g.add(grip_test::sphere_contact<double>(0.5, 0.0, 0.05)) == Status::Ok);
  (void)g.contact(0);
  (void)g.inverse_weight(0);
  CHECK(g_failures == 0);
  (void)g.contact(1);
  CHECK(g_failures == expected);
  (void)g.inverse_weight(2);
  CHECK(g_failures == 2 * expected);

  GraspModes<Grasp<Dynamic, HardFinger, double, 4>> modes;
  modes.count = 1;
  (void)modes.mode(0);
  CHECK(g_failures == 2 * expected);
  (void)modes.is_sliding(1);
  CHECK(g_failures == 3 * expected);

  HandContacts<double> hand;
  (void)hand[0];
  CHECK(g_failures == 4 * expected);
}

TEST_CASE("The unchecked accessors assert their index: Shape, SphereTree, TriangleMesh") {
  Recorder r;
  const Shape<double> shape(make_sphere(0.05));
  (void)shape.primitive(0);
  CHECK(g_failures == 0);
  (void)shape.primitive(1);
  CHECK(g_failures == expected);

  SphereTree<double, 4> tree;
  REQUIRE(tree.add_root(Vector3<double>::Zero(), 1.0) == 0);
  (void)tree.node(0);
  CHECK(g_failures == expected);
  (void)tree.node(1);
  CHECK(g_failures == 2 * expected);

  static TriangleMesh<double, 8, 8> mesh;
  mesh.clear();
  REQUIRE(mesh.add_vertex(Vector3<double>::Zero()) == 0);
  (void)mesh.vertex(0);
  CHECK(g_failures == 2 * expected);
  (void)mesh.vertex(1);
  (void)mesh.triangle(0);
  CHECK(g_failures == 4 * expected);
}

}  // namespace assert_test
