// Triangle meshes and spherical octrees from Python (offline set-up, heap storage): meshes
// read from OBJ or STL files or bytes or built from arrays, checked (a ValueError names the
// issue and where), with their exact signed distance; the spherical octree of a shape or a
// mesh; and the hand's contacts with a mesh, by the octree or directly.

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "mesh.hpp"

namespace grip_python {
namespace {

PyMesh load(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  long size = -1;
  if (f != nullptr && std::fseek(f, 0, SEEK_END) == 0) size = std::ftell(f);
  if (f != nullptr) std::fclose(f);
  if (size < 0) invalid(path + ": cannot be opened");
  std::vector<char> buffer(static_cast<std::size_t>(size) + 1);
  PyMesh m;
  m.finish(grip::read_mesh_file(path.c_str(), buffer.data(), buffer.size(), *m.mesh), path);
  return m;
}

PyMesh from_bytes(const py::bytes& data, const std::string& format) {
  const std::string text = data;
  PyMesh m;
  if (format == "obj")
    m.finish(grip::read_obj(text.data(), text.size(), *m.mesh), "OBJ data");
  else if (format == "stl")
    m.finish(grip::read_stl(text.data(), text.size(), *m.mesh), "STL data");
  else
    invalid("format must be 'obj' or 'stl', not '" + format + "'");
  return m;
}

PyMesh from_arrays(const py::handle& vertices, const py::handle& triangles) {
  const Array v = rows3(vertices, "vertices");
  // As numbers, so that a fractional index is refused rather than truncated.
  const Array t = numbers(triangles, "triangles");
  if (!t || t.ndim() != 2 || t.shape(1) != 3) invalid("triangles must be integers of shape (t, 3)");
  if (v.shape(0) > mesh_vertices || t.shape(0) > mesh_triangles)
    invalid("a mesh holds at most " + std::to_string(mesh_vertices) + " vertices and " +
            std::to_string(mesh_triangles) + " triangles");
  PyMesh m;
  std::vector<int> index(static_cast<std::size_t>(v.shape(0)));
  for (py::ssize_t i = 0; i < v.shape(0); ++i) {
    index[static_cast<std::size_t>(i)] = m.mesh->add_vertex(grip::Vector3<double>(v.at(i, 0), v.at(i, 1), v.at(i, 2)));
    if (index[static_cast<std::size_t>(i)] < 0) invalid("vertices[" + std::to_string(i) + "] cannot be added");
  }
  for (py::ssize_t j = 0; j < t.shape(0); ++j) {
    int c[3];
    for (int k = 0; k < 3; ++k) {
      const double x = t.at(j, k);
      if (!(x == std::floor(x))) invalid("triangles[" + std::to_string(j) + "] must hold integers (vertex indices)");
      if (x < 0 || x >= double(v.shape(0)))
        invalid("triangles[" + std::to_string(j) + "] refers to a vertex that does not exist");
      c[k] = index[static_cast<std::size_t>(x)];
    }
    if (m.mesh->add_triangle(c[0], c[1], c[2]) < 0) invalid("triangles[" + std::to_string(j) + "] cannot be added");
  }
  m.finish(m.mesh->finalize(), "the arrays");
  return m;
}

}  // namespace

void bind_mesh(py::module_& m) {
  m.attr("max_mesh_vertices") = mesh_vertices;
  m.attr("max_mesh_triangles") = mesh_triangles;
  py::class_<PyMesh>(m, "Mesh",
                     "A closed, consistently oriented triangle mesh (checked when made) with its exact signed "
                     "distance (negative inside). Offline storage from the heap: up to max_mesh_vertices and "
                     "max_mesh_triangles.")
      .def_static("load", &load, py::arg("path"), "reads an .obj or .stl (binary or ASCII) file")
      .def_static("from_bytes", &from_bytes, py::arg("data"), py::arg("format"),
                  "OBJ or STL content: format 'obj' or 'stl'")
      .def_static("from_arrays", &from_arrays, py::arg("vertices"), py::arg("triangles"),
                  "vertices (v, 3) (m) and triangles (t, 3) (indices, counter-clockwise seen from outside)")
      .def_property_readonly("vertices",
                             [](const PyMesh& x) {
                               RowMatrix v(x.mesh->vertex_count(), 3);
                               for (int i = 0; i < x.mesh->vertex_count(); ++i)
                                 v.row(i) = x.mesh->vertex(i).transpose();
                               return v;
                             })
      .def_property_readonly("triangle_count", [](const PyMesh& x) { return x.mesh->triangle_count(); })
      .def_property_readonly(
          "volume", [](const PyMesh& x) { return x.mesh->volume(); }, "enclosed volume (m^3)")
      .def_property_readonly("components", [](const PyMesh& x) { return x.mesh->report().components; })
      .def_property_readonly(
          "flipped", [](const PyMesh& x) { return x.mesh->report().flipped; },
          "the file's triangles faced inwards and were turned")
      .def(
          "distance", [](const PyMesh& x, const py::handle& p) { return distances(*x.shape, p); }, py::arg("points"),
          "(distance (m,), outward normal (m, 3)) at points (m, 3): negative inside");

  py::class_<PyOctree>(m, "SphericalOctree",
                       "The paper's spherical octree of a Shape or a Mesh, to max_depth (0 .. 15): the broad phase "
                       "of hand_contacts. Storage from the heap (up to 65 536 cells).")
      .def(py::init([](const py::object& field, Integer max_depth) {
             const int depth = max_depth.get("max_depth");
             PyOctree o;
             o.field = field;
             grip::Status st = grip::Status::InvalidInput;
             if (py::isinstance<PyMesh>(field))
               st = o.tree->build(*field.cast<const PyMesh&>().shape, depth);
             else if (py::isinstance<grip::Shape<double, 4>>(field))
               st = o.tree->build(field.cast<const grip::Shape<double, 4>&>(), depth);
             else
               invalid("field must be a grip.Shape or a grip.Mesh");
             if (st != grip::Status::Ok)
               invalid(
                   "the octree cannot be built: max_depth must be 0 .. 15 and the cells fit in 65 536 (this one "
                   "needs " +
                   std::to_string(o.tree->required_capacity()) + ")");
             return o;
           }),
           py::arg("field"), py::arg("max_depth"))
      .def_property_readonly("cells", [](const PyOctree& o) { return o.tree->required_capacity(); });
}

}  // namespace grip_python
