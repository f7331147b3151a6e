#pragma once
/// \file
/// Readers of Wavefront OBJ and STL (binary and ASCII) from a memory buffer into a
/// TriangleMesh, and a file convenience. Offline set-up code: no heap, no exceptions, no
/// locale; a reader never reads past `size` (the buffer need not end in NUL) and never
/// writes past the mesh's storage. Each reader clears the mesh, reads, then calls finalize()
/// and returns its report (or the reader's own refusal, with the 1-based `line` of a text
/// statement or the `element` = facet of a binary STL). Coordinates are taken as they are:
/// grip works in metres, so scale a file written in millimetres yourself.
///
/// OBJ: `v x y z` (up to 4 further numbers, a weight or a colour, are ignored); `f` with 3 or
/// more vertex references of the forms i, i/j, i//k, i/j/k, where i is 1-based or negative
/// (-1 is the last vertex defined so far) and must name a vertex defined above; polygons are
/// fan-triangulated (v0, v_k, v_k+1). Comments (#, also after a statement), blank lines, CRLF
/// and a UTF-8 byte-order mark are accepted; vn, vt, vp, o, g, s, usemtl, mtllib, l, p and
/// the other statements of the OBJ specification are ignored; any other keyword is Malformed.
///
/// STL: binary when the size is exactly 84 + 50 n for the declared facet count n (even if the
/// header begins with "solid"); otherwise ASCII when the text begins with "solid", else
/// binary. A binary file is refused before reading any facet if it is shorter than declared
/// (Truncated), declares more facets than the mesh holds (TooManyTriangles) or is longer than
/// declared (Malformed). ASCII: solid / facet [normal nx ny nz] / outer loop / vertex x y z
/// (three times) / endloop / endfacet / endsolid, keywords in any case, any blanks and line
/// ends between tokens, several solids in one file; the facet normal is read and ignored
/// (finalize() recomputes normals; "nan" is tolerated there). A file beginning with "solid"
/// that fails as ASCII but holds binary bytes gets the binary diagnosis.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "grip/core/scalar_traits.hpp"
#include "grip/geometry/mesh_text.hpp"
#include "grip/geometry/triangle_mesh.hpp"

namespace grip {

/// Reads a Wavefront OBJ text of `size` bytes into `mesh` (cleared first) and finalizes it.
template <class Scalar, int V, int T>
MeshReport read_obj(const char* data, std::size_t size, TriangleMesh<Scalar, V, T>& mesh);

/// Reads a binary or ASCII STL of `size` bytes into `mesh` (cleared first, duplicate
/// vertices welded) and finalizes it.
template <class Scalar, int V, int T>
MeshReport read_stl(const char* data, std::size_t size, TriangleMesh<Scalar, V, T>& mesh);

/// Reads the file at `path` into the caller's `buffer` of `buffer_size` bytes with
/// std::fopen and std::fread, then reads it by its extension (.obj or .stl, any case).
/// FileError if it cannot be opened or read or is larger than the buffer; UnknownFormat for
/// another extension (the file is then not opened).
template <class Scalar, int V, int T>
MeshReport read_mesh_file(const char* path, char* buffer, std::size_t buffer_size, TriangleMesh<Scalar, V, T>& mesh);

namespace detail {

/// A reader's refusal: the mesh's counts and where the problem is.
template <class Mesh>
MeshReport refuse_read(const Mesh& mesh, MeshIssue issue, long line, long element, long declared = -1) {
  MeshReport r;
  r.status = Status::InvalidInput;
  r.issue = issue;
  r.line = line;
  r.element = element;
  r.declared_triangles = declared;
  r.vertices = mesh.vertex_count();
  r.triangles = mesh.triangle_count();
  return r;
}

/// Parses a coordinate token into Scalar: Ok only if finite and within max_magnitude.
template <class Scalar>
NumberParse parse_coordinate(const char* b, const char* e, Scalar& out) {
  double v = 0.0;
  const NumberParse r = parse_real(b, e, v);
  if (r != NumberParse::Ok) return r;
  out = static_cast<Scalar>(v);
  if (!(std::abs(out) <= ScalarTraits<Scalar>::max_magnitude)) return NumberParse::NonFinite;
  return NumberParse::Ok;
}

/// True if [b, e) is a statement the OBJ specification defines but grip ignores.
inline bool obj_ignored_keyword(const char* b, const char* e) {
  static constexpr const char* words[] = {
      "vn",       "vt",     "vp",     "o",      "g",          "s",         "usemtl", "mtllib", "l",
      "p",        "cstype", "deg",    "bmat",   "step",       "curv",      "curv2",  "surf",   "parm",
      "trim",     "hole",   "scrv",   "sp",     "end",        "con",       "mg",     "bevel",  "c_interp",
      "d_interp", "lod",    "maplib", "usemap", "shadow_obj", "trace_obj", "ctech",  "stech"};
  for (const char* w : words)
    if (equals_word(b, e, w)) return true;
  return false;
}

/// One OBJ vertex reference i, i/j, i//k or i/j/k: the source vertex index (0-based) of i,
/// or -1 with `issue` set.
inline long obj_reference(const char* b, const char* e, long defined, MeshIssue& issue) {
  long long i = 0, unused = 0;
  const char* s = b;
  issue = MeshIssue::Malformed;
  if (!parse_integer(s, e, i, s)) return -1;
  if (s < e && *s == '/') {
    ++s;
    if (s < e && *s == '/') {  // i//k
      if (!parse_integer(s + 1, e, unused, s)) return -1;
    } else {  // i/j or i/j/k
      if (!parse_integer(s, e, unused, s)) return -1;
      if (s < e && *s == '/' && !parse_integer(s + 1, e, unused, s)) return -1;
    }
  }
  if (s != e) return -1;
  issue = MeshIssue::IndexOutOfRange;
  const long long k = i > 0 ? i - 1 : defined + i;
  if (i == 0 || k < 0 || k >= defined) return -1;
  issue = MeshIssue::None;
  return static_cast<long>(k);
}

/// Reads a little-endian 32-bit unsigned integer.
inline std::uint32_t read_le_u32(const char* p) {
  const unsigned char* u = reinterpret_cast<const unsigned char*>(p);
  return static_cast<std::uint32_t>(u[0]) | (static_cast<std::uint32_t>(u[1]) << 8) |
         (static_cast<std::uint32_t>(u[2]) << 16) | (static_cast<std::uint32_t>(u[3]) << 24);
}

/// Reads a little-endian IEEE 754 binary32.
inline float read_le_f32(const char* p) {
  const std::uint32_t bits = read_le_u32(p);
  float f = 0.0f;
  std::memcpy(&f, &bits, 4);
  return f;
}

/// True if the first bytes hold a NUL or a control character other than blanks: not text.
inline bool looks_binary(const char* data, std::size_t size) {
  const std::size_t n = size < 512 ? size : 512;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(data[i]);
    if (c == 0x7f || (c < 0x20 && !is_text_space(static_cast<char>(c)))) return true;
  }
  return false;
}

/// The binary STL reader (the caller cleared the mesh).
template <class Scalar, int V, int T>
MeshReport read_stl_binary(const char* data, std::size_t size, TriangleMesh<Scalar, V, T>& mesh) {
  using Mesh = TriangleMesh<Scalar, V, T>;
  if (size < 84) return refuse_read(mesh, size == 0 ? MeshIssue::Empty : MeshIssue::Truncated, 0, -1);
  const std::uint32_t n = read_le_u32(data + 80);
  const long declared = static_cast<long>(n);
  const std::uint64_t need = 84 + 50 * static_cast<std::uint64_t>(n);
  if (need > size) return refuse_read(mesh, MeshIssue::Truncated, 0, -1, declared);
  if (n > static_cast<std::uint32_t>(Mesh::max_triangles))
    return refuse_read(mesh, MeshIssue::TooManyTriangles, 0, -1, declared);
  if (need < size) return refuse_read(mesh, MeshIssue::Malformed, 0, -1, declared);
  for (std::uint32_t f = 0; f < n; ++f) {
    const char* rec = data + 84 + 50 * static_cast<std::size_t>(f) + 12;  // skip the normal
    int idx[3] = {-1, -1, -1};
    for (int k = 0; k < 3; ++k) {
      Vector3<Scalar> p = Vector3<Scalar>::Zero();
      for (int c = 0; c < 3; ++c) {
        const float x = read_le_f32(rec + 12 * k + 4 * c);
        if (!std::isfinite(x) || !(std::abs(static_cast<Scalar>(x)) <= ScalarTraits<Scalar>::max_magnitude))
          return refuse_read(mesh, MeshIssue::NonFinite, 0, static_cast<long>(f), declared);
        p(c) = static_cast<Scalar>(x);
      }
      idx[k] = mesh.add_vertex(p);
      if (idx[k] < 0) return refuse_read(mesh, MeshIssue::TooManyVertices, 0, static_cast<long>(f), declared);
    }
    if (mesh.add_triangle(idx[0], idx[1], idx[2]) < 0)
      return refuse_read(mesh, MeshIssue::TooManyTriangles, 0, static_cast<long>(f), declared);
  }
  MeshReport r = mesh.finalize();
  r.declared_triangles = declared;
  return r;
}

/// Expects the next token to be keyword `w` (any case): None, Truncated at the end, or Malformed.
inline MeshIssue expect_keyword(TextCursor& in, const char* w) {
  const char *b = nullptr, *e = nullptr;
  if (!in.next_token(b, e)) return MeshIssue::Truncated;
  return equals_word(b, e, w) ? MeshIssue::None : MeshIssue::Malformed;
}

/// Reads three numbers; `strict` refuses nan/inf text (vertices), otherwise it is tolerated
/// (normals, which are ignored).
template <class Scalar>
MeshIssue read_triple(TextCursor& in, Vector3<Scalar>& v, bool strict) {
  for (int c = 0; c < 3; ++c) {
    const char *b = nullptr, *e = nullptr;
    if (!in.next_token(b, e)) return MeshIssue::Truncated;
    Scalar x = Scalar(0);
    const NumberParse r = parse_coordinate(b, e, x);
    if (r == NumberParse::Malformed) return MeshIssue::Malformed;
    if (r == NumberParse::NonFinite && strict) return MeshIssue::NonFinite;
    v(c) = x;
  }
  return MeshIssue::None;
}

/// The ASCII STL reader (the caller cleared the mesh; the text begins with "solid").
template <class Scalar, int V, int T>
MeshReport read_stl_ascii(const char* data, std::size_t size, TriangleMesh<Scalar, V, T>& mesh) {
  TextCursor in(data, size);
  const char *b = nullptr, *e = nullptr;
  in.next_token(b, e);  // "solid", checked by the caller
  in.skip_line();       // the solid's name
  for (;;) {
    if (!in.next_token(b, e)) return refuse_read(mesh, MeshIssue::Truncated, in.line, -1);
    const long line = in.line;
    if (equals_word(b, e, "endsolid")) {
      in.skip_line();
      if (!in.next_token(b, e)) break;
      if (!equals_word(b, e, "solid")) return refuse_read(mesh, MeshIssue::Malformed, in.line, -1);
      in.skip_line();
      continue;
    }
    if (!equals_word(b, e, "facet")) return refuse_read(mesh, MeshIssue::Malformed, line, -1);
    Vector3<Scalar> p = Vector3<Scalar>::Zero();
    if (!in.next_token(b, e)) return refuse_read(mesh, MeshIssue::Truncated, in.line, -1);
    MeshIssue issue = MeshIssue::None;
    if (equals_word(b, e, "normal")) {
      issue = read_triple(in, p, false);
      if (issue == MeshIssue::None) issue = expect_keyword(in, "outer");
    } else if (!equals_word(b, e, "outer")) {
      issue = MeshIssue::Malformed;
    }
    if (issue == MeshIssue::None) issue = expect_keyword(in, "loop");
    int idx[3] = {-1, -1, -1};
    for (int k = 0; k < 3 && issue == MeshIssue::None; ++k) {
      issue = expect_keyword(in, "vertex");
      if (issue == MeshIssue::None) issue = read_triple(in, p, true);
      if (issue == MeshIssue::None && (idx[k] = mesh.add_vertex(p)) < 0) issue = MeshIssue::TooManyVertices;
    }
    if (issue == MeshIssue::None) issue = expect_keyword(in, "endloop");
    if (issue == MeshIssue::None) issue = expect_keyword(in, "endfacet");
    if (issue == MeshIssue::None && mesh.add_triangle(idx[0], idx[1], idx[2]) < 0) issue = MeshIssue::TooManyTriangles;
    if (issue != MeshIssue::None) return refuse_read(mesh, issue, in.line, -1);
  }
  return mesh.finalize();
}

}  // namespace detail

template <class Scalar, int V, int T>
MeshReport read_obj(const char* data, std::size_t size, TriangleMesh<Scalar, V, T>& mesh) {
  mesh.clear();
  detail::TextCursor in(data, size);
  const char *b = nullptr, *e = nullptr;
  while (!in.end()) {
    const long line = in.line;
    if (!in.token(b, e, true)) {  // blank line or comment
      in.skip_line();
      continue;
    }
    if (detail::equals_word(b, e, "v")) {
      Vector3<Scalar> p = Vector3<Scalar>::Zero();
      int n = 0;
      while (in.token(b, e, true)) {
        Scalar x = Scalar(0);
        const detail::NumberParse r = detail::parse_coordinate(b, e, x);
        if (r == detail::NumberParse::Malformed || n >= 7)
          return detail::refuse_read(mesh, MeshIssue::Malformed, line, -1);
        if (r == detail::NumberParse::NonFinite) return detail::refuse_read(mesh, MeshIssue::NonFinite, line, -1);
        if (n < 3) p(n) = x;
        ++n;
      }
      if (n < 3) return detail::refuse_read(mesh, MeshIssue::Malformed, line, -1);
      if (mesh.add_source_vertex(p) < 0) return detail::refuse_read(mesh, MeshIssue::TooManyVertices, line, -1);
    } else if (detail::equals_word(b, e, "f")) {
      int first = -1, previous = -1, n = 0;
      while (in.token(b, e, true)) {
        MeshIssue issue = MeshIssue::None;
        const long k = detail::obj_reference(b, e, mesh.source_vertex_count(), issue);
        if (k < 0) return detail::refuse_read(mesh, issue, line, -1);
        const int v = mesh.source_vertex(k);
        if (n == 0) first = v;
        if (n >= 2 && mesh.add_triangle(first, previous, v) < 0)
          return detail::refuse_read(mesh, MeshIssue::TooManyTriangles, line, -1);
        previous = v;
        ++n;
      }
      if (n < 3) return detail::refuse_read(mesh, MeshIssue::Malformed, line, -1);
    } else if (!detail::obj_ignored_keyword(b, e)) {
      return detail::refuse_read(mesh, MeshIssue::Malformed, line, -1);
    }
    in.skip_line();  // the rest: a comment, or an ignored statement
  }
  return mesh.finalize();
}

template <class Scalar, int V, int T>
MeshReport read_stl(const char* data, std::size_t size, TriangleMesh<Scalar, V, T>& mesh) {
  mesh.clear();
  if (data == nullptr || size == 0) return detail::refuse_read(mesh, MeshIssue::Empty, 0, -1);
  if (size >= 84 && 84 + 50 * static_cast<std::uint64_t>(detail::read_le_u32(data + 80)) == size)
    return detail::read_stl_binary(data, size, mesh);
  detail::TextCursor in(data, size);
  const char *b = nullptr, *e = nullptr;
  if (!(in.next_token(b, e) && detail::equals_word(b, e, "solid"))) return detail::read_stl_binary(data, size, mesh);
  const MeshReport ascii = detail::read_stl_ascii(data, size, mesh);
  if (ascii.ok() || size < 84 || !detail::looks_binary(data, size)) return ascii;
  mesh.clear();
  return detail::read_stl_binary(data, size, mesh);
}

template <class Scalar, int V, int T>
MeshReport read_mesh_file(const char* path, char* buffer, std::size_t buffer_size, TriangleMesh<Scalar, V, T>& mesh) {
  mesh.clear();
  if (path == nullptr || buffer == nullptr) return detail::refuse_read(mesh, MeshIssue::FileError, 0, -1);
  const std::size_t len = std::strlen(path);
  const char* ext = len >= 4 ? path + len - 4 : path;
  const bool obj = len >= 4 && detail::equals_word(ext, path + len, ".obj");
  const bool stl = len >= 4 && detail::equals_word(ext, path + len, ".stl");
  if (!obj && !stl) return detail::refuse_read(mesh, MeshIssue::UnknownFormat, 0, -1);
  std::FILE* f = std::fopen(path, "rb");
  if (f == nullptr) return detail::refuse_read(mesh, MeshIssue::FileError, 0, -1);
  const std::size_t n = std::fread(buffer, 1, buffer_size, f);
  const bool failed = std::ferror(f) != 0;
  const bool larger = !failed && n == buffer_size && std::fgetc(f) != EOF;
  std::fclose(f);
  if (failed || larger) return detail::refuse_read(mesh, MeshIssue::FileError, 0, -1);
  return obj ? read_obj(buffer, n, mesh) : read_stl(buffer, n, mesh);
}

}  // namespace grip
