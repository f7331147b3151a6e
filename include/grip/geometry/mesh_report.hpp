#pragma once
/// \file
/// What loading and checking a triangle mesh found: MeshIssue, its names, and MeshReport, the
/// result of TriangleMesh::finalize() and of the readers of mesh_io.hpp.
///
/// A report's status is Ok or InvalidInput; `issue` says why (None when Ok). The readers fill
/// `line` (1-based, for a statement of a text file) or `element` (a facet of a binary STL, a
/// triangle of the mesh) to point at the first problem found.

#include <cstdint>

#include "grip/core/status.hpp"

namespace grip {

/// Why a mesh was refused.
enum class MeshIssue : std::uint8_t {
  None,                     ///< No problem: the mesh is accepted.
  Empty,                    ///< No triangle at all (empty input, or only vertices).
  Malformed,                ///< A statement does not follow the format's grammar.
  Truncated,                ///< The input ends inside a statement, a facet or a solid.
  NonFinite,                ///< A coordinate is NaN or infinite, is written "nan" or "inf", overflows,
                            ///< or exceeds ScalarTraits::max_magnitude.
  IndexOutOfRange,          ///< An OBJ face refers to vertex 0 or to a vertex not defined above it.
  TooManyVertices,          ///< More distinct vertices (OBJ: `v` statements) than the mesh holds.
  TooManyTriangles,         ///< More triangles than the mesh holds (also a binary STL's declared count).
  DegenerateTriangle,       ///< A triangle repeats a vertex or has zero area (to rounding).
  NotClosed,                ///< An edge belongs to one triangle only: the surface has a hole.
  NonManifold,              ///< An edge belongs to more than two triangles, or the triangles around a
                            ///< vertex form more than one fan (surfaces touching at a vertex).
  InconsistentOrientation,  ///< Two triangles run along their common edge in the same direction.
  FoldedSurface,            ///< Zero thickness: two faces back to back along an edge, a vertex whose
                            ///< faces cancel, or a component of zero volume.
  Overlapping,              ///< A closed component lies inside another with the same orientation, or a
                            ///< cavity lies outside every solid: overlapping or mis-nested components.
  FileError,                ///< The file cannot be opened or read, or does not fit in the buffer.
  UnknownFormat,            ///< The file name ends neither in .obj nor in .stl.
};

/// A short English name of the issue, for logs ("none", "not closed", ...).
constexpr const char* to_string(MeshIssue issue) {
  switch (issue) {
    case MeshIssue::None: return "none";
    case MeshIssue::Empty: return "empty";
    case MeshIssue::Malformed: return "malformed";
    case MeshIssue::Truncated: return "truncated";
    case MeshIssue::NonFinite: return "non-finite number";
    case MeshIssue::IndexOutOfRange: return "index out of range";
    case MeshIssue::TooManyVertices: return "too many vertices";
    case MeshIssue::TooManyTriangles: return "too many triangles";
    case MeshIssue::DegenerateTriangle: return "degenerate triangle";
    case MeshIssue::NotClosed: return "not closed";
    case MeshIssue::NonManifold: return "non-manifold";
    case MeshIssue::InconsistentOrientation: return "inconsistent orientation";
    case MeshIssue::FoldedSurface: return "folded surface";
    case MeshIssue::Overlapping: return "overlapping components";
    case MeshIssue::FileError: return "file error";
    case MeshIssue::UnknownFormat: return "unknown format";
  }
  return "unknown";
}

/// The outcome of finalizing or reading a mesh.
struct MeshReport {
  Status status{Status::InvalidInput};  ///< Ok, or InvalidInput with an issue.
  MeshIssue issue{MeshIssue::Empty};    ///< Why the mesh was refused; None when Ok.
  long line{0};                         ///< 1-based line of the statement at fault in a text file; 0 if none.
  long element{-1};                     ///< Triangle at fault (the mesh's, or a binary STL's facet); -1 if none.
  long declared_triangles{-1};          ///< The facet count a binary STL declares; -1 for other inputs.
  int vertices{0};                      ///< Vertices in the mesh (after welding).
  int triangles{0};                     ///< Triangles in the mesh.
  int components{0};                    ///< Connected closed surfaces (finalize, when it got that far).
  bool flipped{false};                  ///< The mesh was oriented inward and finalize turned every triangle.

  /// True when status is Ok.
  bool ok() const { return status == Status::Ok; }
};

}  // namespace grip
