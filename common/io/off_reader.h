// A small strict reader for ASCII OFF files (Geomview's Object File Format), enough for the CGAL
// meshes that samples/fetch_data.sh fetches, without MeshLab: OFF, COFF, NOFF and CNOFF (colours
// read and ignored, NOFF normals kept), polygons fanned into triangles. Anything malformed,
// truncated or of another variant is refused with the file name, line number and reason. Numbers are
// parsed with std::from_chars: independent of the C locale (Qt may set one).
// Details: docs/design-notes.md, "`common/io/off_reader.h`: how it works".
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
