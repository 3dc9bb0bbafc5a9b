// Wavefront OBJ with per-wedge texture coordinates: how meshlabserver exchanges textured meshes with
// us (MeshLab's OBJ exporter writes "vt" per wedge, "f v/vt[/vn]", and a "mtllib" whose material
// names the texture with "map_Kd"). The reader takes what MeshLab and common tools write (polygons
// fanned, relative indices, one texture); a malformed file throws ObjReadError
// ("<path>:<line>: <reason>"), while what can be dropped (mixed normals, a missing .mtl) is read
// without it and reported in `warnings`.
// Details: docs/design-notes.md, "`common/io/obj_mesh.h`: how it works".
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
