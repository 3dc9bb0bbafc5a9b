// A streaming reader for triangle meshes in PLY files of any size (scans that do not fit in memory,
// Granier et al. 2007's out-of-core setting): the file is read once, front to back, through a buffer
// of bounded size, and its vertices then its faces are handed to the caller in chunks; nothing of the
// mesh is kept by the reader. ASCII and binary (either endianness); positions and optional normals;
// polygons fanned into triangles; every other property and element skipped. Damaged or hostile
// input (including NaN or infinite coordinates) throws PlyStreamError with the byte offset and a fix.
// Details: docs/out-of-core.md, "`common/io/ply_stream_reader.h`: how it works".
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
