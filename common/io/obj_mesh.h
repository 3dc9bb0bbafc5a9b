// Wavefront OBJ with per-wedge texture coordinates: how meshlabserver exchanges textured meshes
// with us (MeshLab's OBJ exporter writes "vt" per wedge, "f v/vt[/vn]", and a "mtllib" whose
// material names the texture with "map_Kd").
//
// Read:
//   v x y z [w | r g b]        (w and MeshLab's per-vertex colours are ignored)
//   vt u v [w]                 (w ignored)
//   vn x y z
//   f a b c ...                with corners v, v/vt, v/vt/vn or v//vn; 1-based or negative
//                              (relative: -1 = the last one read so far) indices; polygons are
//                              triangulated as a fan from the first corner (right for convex ones)
//   mtllib file.mtl            the first material library (relative to the OBJ's folder); its
//                              map_Kd (of the first material used by `usemtl`, else the first one
//                              with a map_Kd) is the texture
//   comments from '#', blank lines, CRLF, line continuations ('\' at the end of a line);
//   o, g, s, usemtl, l, p and other statements are ignored.
// Texture coordinates: every face corner has a vt, or none has (then wedgeUv is empty).
// Normals: when every face corner has a vn, each vertex gets the normalised mean of the vn its
// corners use (MeshLab writes one vn per vertex, so this is that vn); otherwise no normals.
// Refused with "<path>:<line>: <reason>": a malformed number, vertex, vt, vn or face statement, an
// index 0 or out of range, a face with fewer than 3 corners, a file mixing corners with and
// without vt. Not errors (the mesh is read and `warnings` says what was dropped): corners mixing
// with and without vn (no normals), a missing or unreadable .mtl (no texture). Only one texture
// is kept (see mtllib above).
#pragma once

#include "errors/error_categories.h"

#include "geometry/triangle_mesh.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

struct ObjReadError : FileError {
    using FileError::FileError;
};
struct ObjWriteError : FileError {
    using FileError::FileError;
};

struct ObjMesh {
    TriangleMesh mesh;
    std::vector<float> wedgeUv;         // 6 floats per face (texture_atlas.h), or empty
    std::string textureName;            // map_Kd as written in the .mtl (empty: none)
    std::string texturePath;            // textureName resolved against the .mtl's folder
    std::vector<std::string> warnings;  // e.g. a mtllib that could not be read
};

ObjMesh readObj(const std::string& path);

// Writes `mesh` (positions, normals as "vn" with the vertex's index when present) and, when
// wedgeUv is not empty (6 floats per face), one "vt" per face corner and "f v/vt[/vn]" faces.
// When textureName is not empty, also writes "<path without .obj>.mtl" (or "<path>.mtl" when the
// name does not end in .obj) with one material whose map_Kd is textureName (written as given:
// relative to the OBJ's folder, as MeshLab expects), and the OBJ refers to it with mtllib/usemtl.
// Floats are written in their shortest round-trip form: a write-read cycle is exact.
// Throws ObjWriteError for inconsistent input or an I/O failure.
void writeObj(const std::string& path, const TriangleMesh& mesh, const std::vector<float>& wedgeUv,
              const std::string& textureName = "");

}  // namespace rad
