// A small strict reader for ASCII OFF files (Geomview's Object File Format), enough for the CGAL
// meshes of docs data.md (samples/fetch_data.sh) without MeshLab.
//
// Accepted:
//   header   "OFF", "COFF", "NOFF" or "CNOFF" (vertex colours are read and ignored; NOFF normals are
//            kept), optionally followed on the same line by the counts;
//   counts   "nVertices nFaces [nEdges]" (nEdges ignored);
//   vertices one per line: x y z [nx ny nz if N] [r g b [a] if C];
//   faces    one per line: k i_1 .. i_k [up to 4 colour values, ignored], k >= 3; polygons are
//            triangulated as a fan from i_1 (right for convex polygons);
//   comments from '#' to the end of a line, blank lines, CRLF line ends.
// Refused, with the file name, line number and reason: binary OFF and the 4OFF / nOFF / ST variants,
// missing or malformed counts, a vertex line with the wrong number of values or a non-finite value,
// a face with fewer than 3 vertices, an index out of range or repeated within the face, a file that
// ends before the announced vertices and faces, and any data after the last face.
// Numbers are parsed with std::from_chars: independent of the C locale (Qt may set one).
#pragma once

#include "errors/error_categories.h"

#include "geometry/triangle_mesh.h"

#include <istream>
#include <stdexcept>
#include <string>

namespace rad {

class OffReadError : public FileError {
public:
    using FileError::FileError;
};

// Reads the file; throws OffReadError ("<path>:<line>: <reason>") when it cannot be opened or is
// malformed. The mesh has normals only for NOFF files (see geometry/mesh_normals.h otherwise).
TriangleMesh readOff(const std::string& path);

// Same from a stream; `sourceName` prefixes the error messages.
TriangleMesh parseOff(std::istream& in, const std::string& sourceName = "<OFF>");

}  // namespace rad
