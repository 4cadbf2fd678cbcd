#pragma once
// Mesh import and export: Wavefront OBJ and PLY. Used for targets placed in scenes (import) and for
// exporting trees and whole scenes (export). Units are whatever the file holds (Sylva writes
// metres, Z up); no axis conversion is applied.

#include "geometry/mesh.h"

#include <filesystem>
#include <span>
#include <string>

namespace sylva {

// Reads a mesh, choosing the format by file extension (.obj or .ply, any case).
//
// OBJ: `v x y z [w | r g b]`, `vn`, `vt u [v [w]]`, and `f` with corners `v`, `v/vt`, `v//vn` or
// `v/vt/vn` (1-based; negative = relative to the elements defined so far; an index must refer to
// an element defined before the face). Polygons are fan-triangulated: (0,1,2), (0,2,3), ...
// `o g usemtl mtllib s l p vp` lines and `#` comments are accepted and ignored.
// PLY: ascii, binary_little_endian and binary_big_endian. `vertex` needs x y z; nx ny nz and
// u v / s t / texture_u texture_v / texture_s texture_t are read when present. `face` needs a
// list `vertex_indices` (or `vertex_index`) of any integer type; polygons are fan-triangulated.
// Other elements and properties are skipped.
//
// The result is single-indexed and keeps the file's vertex order: in OBJ the first (vt, vn) seen
// with position v gives vertex v its attributes, and every further distinct combination appends a
// copy of the position. normals/uvs are filled only when every face corner has them (otherwise
// they are left empty); vertices no face uses get uv (0,0) and normal (0,0,1).
//
// Every malformed input throws sylva::ParseError "file:line: what was expected" (line 0 for
// binary PLY data, with the byte offset in the message; also line 0 for a missing file or an
// unknown extension). Indices are validated; truncated or garbage input never crashes or hangs.
TriangleMesh read_mesh(const std::filesystem::path& file);

// Writes a tree: stem triangles with per-vertex normals and uvs (normals are computed,
// area-weighted, and uvs set to 0 when the stems lack them), then leaves as quads with uv
// (0,0),(1,0),(1,1),(0,1) and the quad's normal, grouped by leaf shape. OBJ: `g stems`, then per
// shape `g leaves_<name>` and `usemtl leaves_<name>` (names from leaf_shape_name). PLY:
// binary_little_endian with vertex x y z nx ny nz u v (float) and face `list uchar int
// vertex_indices` plus `uchar leaf_shape` (the LeafShape value, 255 for stem faces). Atomic
// (core/atomic_file.h): on failure `file` is left as it was and sylva::Error is thrown (also for an
// inconsistent mesh: bad indices or attribute sizes, refused before anything is written).
void write_obj(const std::filesystem::path& file, const TreeMesh& mesh);
void write_ply(const std::filesystem::path& file, const TreeMesh& mesh);

// Writes a plain triangle mesh as OBJ (v, then vt and vn when present, faces in the matching form).
// Atomic like the TreeMesh writers. Floats are written in shortest round-trip form.
void write_obj(const std::filesystem::path& file, const TriangleMesh& mesh);

// Faces in named groups, each written as `g NAME` and `usemtl NAME` followed by its faces (in mesh
// order), after `mtllib MTLLIB` when that is not empty. `of_triangle[t]` is face t's row of
// `names`; groups without faces are not written. Names must be non-empty and free of white space.
// With no names, the faces are written in mesh order without groups (`of_triangle` unread).
struct ObjGroups {
  std::span<const uint32_t> of_triangle;
  std::span<const std::string> names;
  std::string mtllib;
};
void write_obj(const std::filesystem::path& file, const TriangleMesh& mesh, const ObjGroups& groups);

}  // namespace sylva
