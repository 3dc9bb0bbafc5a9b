// The project's file format: a binary little-endian PLY file whose vertices carry the radiance
// coefficients and frame of every vertex. Any PLY reader can read its geometry and (by property
// name) its coefficients; the exact layout is specified in docs/radiance-ply-format.md.
#pragma once

#include "errors/error_categories.h"

#include "io/radiance_mesh.h"

#include <stdexcept>
#include <string>

namespace rad {

inline constexpr int kRadiancePlyFormatVersion = 1;

// Every failure of readRadiancePly / writeRadiancePly. what() says what is wrong and how to fix it.
struct RadianceFileError : FileError {
    using FileError::FileError;
};

// Empty string when writeRadiancePly can write the mesh; otherwise a sentence saying what is
// inconsistent (array sizes, face indices, non-finite values, radiance field, block names...).
std::string validateRadianceMesh(const RadianceMesh& mesh);

// Validates the mesh, writes it to a temporary file next to `path`, then renames it over `path`:
// a failed save never leaves a partial file and never damages an existing one. Temporary files of
// earlier saves to `path` whose writer process is dead (killed mid-save) are removed first.
// When mesh.radiance is set, the file's normals (nx ny nz) are the radiance frame normals; mesh.normals
// must then be empty or bit-identical to them.
// Throws RadianceFileError on inconsistent input or any I/O failure.
void writeRadiancePly(const std::string& path, const RadianceMesh& mesh);

// Reads a radiance PLY file (or a plain binary little-endian triangle PLY without radiance).
// Strict: refuses anything it cannot read exactly, with a message saying what is wrong and how to fix
// it. When the file has radiance, both mesh.normals and mesh.radiance->frames hold the normals.
// Every declared extra block is returned in mesh.extraBlocks; what the format does not know (unknown
// vertex properties and elements) is skipped and listed in mesh.skippedOnRead.
// Throws RadianceFileError.
RadianceMesh readRadiancePly(const std::string& path);

}  // namespace rad
