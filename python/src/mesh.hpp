#pragma once
// Meshes and octrees as the bindings hold them: heap storage at fixed addresses.

#include <memory>
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include "grasp.hpp"

namespace grip_python {

constexpr int mesh_vertices = 32768;
constexpr int mesh_triangles = 65536;
constexpr int octree_cells = 65536;
using MeshT = grip::TriangleMesh<double, mesh_vertices, mesh_triangles>;
using MeshShapeT = grip::MeshShape<double, mesh_vertices, mesh_triangles>;
using Octree = grip::SphericalOctree<double, octree_cells>;

/// A checked mesh and its distance structure, at fixed addresses (the shape points at the mesh).
struct PyMesh {
  std::unique_ptr<MeshT> mesh{new MeshT()};
  std::unique_ptr<MeshShapeT> shape{new MeshShapeT()};

  void finish(const grip::MeshReport& r, const std::string& source) {
    if (!r.ok()) {
      std::string where;
      if (r.line > 0) where += ", line " + std::to_string(r.line);
      if (r.element >= 0) where += ", triangle " + std::to_string(r.element);
      invalid(source + ": the mesh is refused: " + grip::to_string(r.issue) + where);
    }
    if (shape->build(*mesh) != grip::Status::Ok) invalid(source + ": the mesh's hierarchy could not be built");
  }
};

struct PyOctree {
  std::unique_ptr<Octree> tree{new Octree()};
  py::object field;  ///< the Shape or Mesh it was built from (kept alive)
};

/// (distance (m,), outward normal (m, 3)) of `f` (a Shape or a MeshShape) at points (m, 3).
template <class Field>
py::tuple distances(const Field& f, const py::handle& points) {
  const Array p = rows3(points, "points");
  Eigen::VectorXd d(p.shape(0));
  RowMatrix n(p.shape(0), 3);
  for (py::ssize_t i = 0; i < p.shape(0); ++i) {
    grip::Vector3<double> g;
    d(i) = f.distance(grip::Vector3<double>(p.at(i, 0), p.at(i, 1), p.at(i, 2)), g);
    n.row(i) = g.transpose();
  }
  return py::make_tuple(d, n);
}

}  // namespace grip_python
