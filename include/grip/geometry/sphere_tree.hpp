#pragma once
/// \file
/// A tree of bounding spheres in one flat, fixed-capacity array (no heap): the storage of
/// the spherical octrees of objects (branching factor 8) and of other sphere hierarchies.
///
/// Index arithmetic. Nodes are appended so that the children of every node are contiguous:
/// the children of node i are the indices [first_child(i), first_child(i) + child_count(i)),
/// its parent is parent(i) (-1 for the root, index 0). A builder that processes the nodes
/// in index order and appends the children of the node being processed (breadth-first)
/// satisfies this; add_child() refuses an append that would break it. For a COMPLETE tree of
/// branching B built that way the indices are the classic implicit ones: children of i are
/// B i + 1 ... B i + B and the parent of i > 0 is (i - 1) / B; a pruned octree keeps only
/// some children, so it stores first_child and child_count explicitly.

#include <array>
#include <cstdint>

#include "grip/core/index.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// One node of a SphereTree: a sphere bounding everything below it.
template <class Scalar>
struct SphereNode {
  Vector3<Scalar> center{Vector3<Scalar>::Zero()};  ///< Sphere centre (m), in the tree's frame.
  Scalar radius{0};                                 ///< Sphere radius (m).
  std::int32_t parent{-1};                          ///< Parent index, -1 for the root.
  std::int32_t first_child{0};                      ///< Index of the first child (valid if child_count > 0).
  std::uint8_t child_count{0};                      ///< Number of children, 0 for a leaf.
  std::uint8_t level{0};                            ///< Depth below the root (root 0).
};

/// A sphere tree of at most Capacity nodes, each with at most MaxChildren children, stored
/// in place (sizeof grows with Capacity; put large trees in static storage or a member).
template <class Scalar, int Capacity, int MaxChildren = 8>
class SphereTree {
  static_assert(Capacity >= 1, "a tree holds at least its root");
  static_assert(MaxChildren >= 2 && MaxChildren <= 255, "branching factor in [2, 255]");

 public:
  static constexpr int capacity = Capacity;         ///< Most nodes held.
  static constexpr int max_children = MaxChildren;  ///< Branching factor bound.

  /// Removes all nodes.
  void clear() { size_ = 0; }
  /// Number of nodes.
  int size() const { return size_; }
  /// True if no node is stored.
  bool empty() const { return size_ == 0; }

  /// Makes the tree a single root node; returns its index 0, or -1 if Capacity is 0.
  int add_root(const Vector3<Scalar>& center, Scalar radius) {
    size_ = 0;
    SphereNode<Scalar>& n = nodes_[0];
    n = SphereNode<Scalar>{};
    n.center = center;
    n.radius = radius;
    size_ = 1;
    return 0;
  }

  /// Appends a child of `parent`; returns its index, or -1 (tree unchanged) if the tree is
  /// full, `parent` is not a node, it already has MaxChildren children, or the append would
  /// make its children non-contiguous (another node was appended since its last child).
  int add_child(int parent, const Vector3<Scalar>& center, Scalar radius) {
    if (size_ >= Capacity || parent < 0 || parent >= size_) return -1;
    SphereNode<Scalar>& p = nodes_[detail::idx(parent)];
    if (p.child_count >= MaxChildren) return -1;
    if (p.child_count > 0 && p.first_child + p.child_count != size_) return -1;
    if (p.child_count == 0) p.first_child = size_;
    ++p.child_count;
    SphereNode<Scalar>& n = nodes_[detail::idx(size_)];
    n = SphereNode<Scalar>{};
    n.center = center;
    n.radius = radius;
    n.parent = parent;
    n.level = static_cast<std::uint8_t>(p.level + 1);
    return size_++;
  }

  /// Node i. Precondition (GRIP_ASSERT): 0 <= i < size().
  const SphereNode<Scalar>& node(int i) const {
    GRIP_ASSERT(i < size_);
    return nodes_[detail::idx(i)];
  }
  /// True if node i has no children.
  bool is_leaf(int i) const { return node(i).child_count == 0; }

  /// Number of leaves.
  int leaf_count() const {
    int n = 0;
    for (int i = 0; i < size_; ++i) n += is_leaf(i) ? 1 : 0;
    return n;
  }

 private:
  std::array<SphereNode<Scalar>, detail::idx(Capacity)> nodes_{};
  int size_{0};
};

}  // namespace grip
