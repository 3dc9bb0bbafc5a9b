// A streaming reader for triangle meshes in PLY files of any size (scans that do not fit in memory,
// Granier et al. 2007's out-of-core setting): the file is read once, front to back, through a buffer
// of bounded size, and its vertices then its faces are handed to the caller in chunks. Nothing of the
// mesh is kept by the reader.
//
// Accepted:
//   format   ascii 1.0, binary_little_endian 1.0, binary_big_endian 1.0;
//   vertex   element "vertex" with scalar properties x, y, z (any numeric type, read as float) and,
//            optionally, nx, ny, nz (all three); every other property is skipped whatever its type,
//            lists included;
//   face     element "face" with a list property "vertex_indices" (or "vertex_index") whose length
//            type is an integer type and whose items are an integer type; polygons with k > 3
//            vertices are triangulated as a fan from their first vertex (counted); other face
//            properties are skipped;
//   other elements (edges, materials, ...) are skipped, before, between or after those two.
// Refused with PlyStreamError (byte offset and element index in the message, and a fix): a file
// that is not PLY or has a malformed header, no vertex element or no x / y / z, a face element
// before the vertex element (the faces need the positions), counts the file is too short to hold,
// a truncated file, a face with fewer than 3 vertices, a vertex index out of range, and a vertex
// with a NaN or infinite coordinate (refused rather than skipped: a scan with such vertices is
// damaged, and silently dropping the faces around them would make holes nobody asked for; MeshLab's
// "Remove Unreferenced Vertices" after deleting them repairs the file).
// ASCII numbers are parsed with std::from_chars (independent of the C locale).
#pragma once

#include "errors/error_categories.h"
#include "io/ply_header.h"  // PlyEncoding
#include "progress/progress_callback.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

namespace rad {

// Every failure of the reader. what() names the file, the byte offset (and element index when
// there is one), what is wrong and how to fix it.
struct PlyStreamError : FileError {
    PlyStreamError(const std::string& message, std::uint64_t byteOffset)
        : FileError(message), byteOffset(byteOffset) {}
    std::uint64_t byteOffset = 0;
};

struct PlyStreamInfo {
    PlyEncoding encoding = PlyEncoding::BinaryLittleEndian;
    std::uint64_t vertexCount = 0;
    std::uint64_t faceCount = 0;     // PLY faces (polygons), before triangulation
    bool hasNormals = false;
    std::uint64_t fileBytes = 0;
    std::uint64_t headerBytes = 0;
};

// What a pass saw, filled as it goes.
struct PlyStreamStats {
    std::uint64_t verticesRead = 0;
    std::uint64_t facesRead = 0;       // PLY faces
    std::uint64_t trianglesEmitted = 0;
    std::uint64_t polygonsTriangulated = 0;  // faces with more than 3 vertices
};

// Chunks handed to the callbacks; pointers valid during the call only.
struct PlyVertexChunk {
    std::uint64_t firstIndex = 0;
    std::size_t count = 0;
    const float* positions = nullptr;  // 3 per vertex
    const float* normals = nullptr;    // 3 per vertex, or nullptr when the file has none
};
struct PlyTriangleChunk {
    std::size_t count = 0;
    const std::uint32_t* indices = nullptr;  // 3 per triangle, checked < vertexCount
};

class PlyStreamReader {
public:
    // Opens the file and parses its header (throws PlyStreamError). chunkVertices / chunkTriangles
    // bound the reader's buffers (the byte buffer is 4 MiB).
    explicit PlyStreamReader(std::string path, std::size_t chunkVertices = 1 << 16, std::size_t chunkTriangles = 1 << 16);
    ~PlyStreamReader();
    PlyStreamReader(const PlyStreamReader&) = delete;
    PlyStreamReader& operator=(const PlyStreamReader&) = delete;

    const PlyStreamInfo& info() const { return info_; }

    // One pass over the file from the start: every vertex in chunks, then (unless verticesOnly) every
    // face as triangles in chunks. Either callback may be empty. Progress in [0, 1] by bytes read
    // (OperationCancelled on a stop request). Can be called again for another pass.
    PlyStreamStats read(const std::function<void(const PlyVertexChunk&)>& onVertices,
                        const std::function<void(const PlyTriangleChunk&)>& onTriangles, bool verticesOnly = false,
                        const ProgressCallback& progress = {});

    struct Impl;

private:
    std::string path_;
    std::size_t chunkVertices_, chunkTriangles_;
    PlyStreamInfo info_;
    std::unique_ptr<Impl> impl_;  // owned also when the constructor throws
};

}  // namespace rad
