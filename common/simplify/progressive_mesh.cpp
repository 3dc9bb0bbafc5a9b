#include "simplify/progressive_mesh.h"

#include "geometry/coordinate_range.h"
#include "io/atomic_file.h"
#include "io/radiance_ply.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <stdexcept>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace rad {

namespace {

constexpr char kMagic[] = "radiance-progressive-mesh";
// Version 2 adds base_hash and records_hash (version 1 files, without them, are still read).
constexpr int kFormatVersion = 2;
constexpr std::size_t kFixedRecordBytes = 4 * 3 + 4 * 4;  // removed, survivor, faces after; xyz, cost

std::string kindName(CollapseKind k) { return k == CollapseKind::HalfEdge ? "half-edge" : "full"; }

// Follows removed -> survivor links with path halving (the links only ever point to later survivors).
std::uint32_t representative(std::vector<std::uint32_t>& parent, std::uint32_t v) {
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

// FNV-1a, 64 bits: binds the .rpm to its base and its records to themselves. Not a defence against
// a forger, against accidents: a base saved again in another vertex order, an old .rpm beside a
// new base (a kill between the two renames), records rewritten by a tool.
std::uint64_t fnv1a(const char* data, std::size_t size, std::uint64_t hash = 0xcbf29ce484222325ull) {
    for (std::size_t i = 0; i < size; ++i) {
        hash ^= static_cast<unsigned char>(data[i]);
        hash *= 0x100000001b3ull;
    }
    return hash;
}

std::string hashText(std::uint64_t hash) {
    std::ostringstream text;
    text << "fnv1a64:" << std::hex << std::setw(16) << std::setfill('0') << hash;
    return text.str();
}

std::string readWholeFile(const std::string& path, const char* what) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw ProgressiveMeshError(std::string("cannot open ") + what + " '" + path + "'");
    return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
}

// Replays the collapses on the base's faces and returns the first step after which the recorded
// face count differs from the replay (a changed survivor index, a rewritten count), or -1.
long long firstWrongFaceCount(const RadianceMesh& base, const std::vector<CollapseStep>& steps,
                              const std::vector<std::uint32_t>& faceCountAfter) {
    const std::size_t nv = base.vertexCount(), nf = base.faceCount();
    std::vector<std::uint32_t> parent(nv);
    for (std::size_t v = 0; v < nv; ++v) parent[v] = static_cast<std::uint32_t>(v);
    std::vector<std::vector<std::uint32_t>> incident(nv);
    std::vector<std::uint8_t> alive(nf, 0);
    std::size_t aliveCount = 0;
    for (std::size_t f = 0; f < nf; ++f) {
        const std::uint32_t* t = &base.faces[3 * f];
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        alive[f] = 1;
        ++aliveCount;
        for (int k = 0; k < 3; ++k) incident[t[k]].push_back(static_cast<std::uint32_t>(f));
    }
    for (std::size_t i = 0; i < steps.size(); ++i) {
        const std::uint32_t r = steps[i].removed, s = steps[i].survivor;
        parent[r] = s;
        for (std::uint32_t f : incident[r]) {
            if (!alive[f]) continue;
            std::uint32_t t[3];
            for (int k = 0; k < 3; ++k) t[k] = representative(parent, base.faces[3 * std::size_t(f) + k]);
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
                alive[f] = 0;
                --aliveCount;
            } else {
                incident[s].push_back(f);
            }
        }
        std::vector<std::uint32_t>().swap(incident[r]);
        if (aliveCount != faceCountAfter[i]) return static_cast<long long>(i);
    }
    return -1;
}

std::string folderOf(const std::string& path) {
    const auto slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

}  // namespace

int ProgressiveRadianceMesh::rowFloats() const {
    if (kind != CollapseKind::Full || !base.radiance) return 0;
    return 6 + base.radiance->coefficientsPerVertex();
}

std::size_t ProgressiveRadianceMesh::stepsForFaceCount(std::size_t faces) const {
    if (base.faceCount() <= faces) return 0;
    // faceCountAfter is non-increasing: binary search for the first step at or below `faces`.
    const auto it = std::lower_bound(faceCountAfter.begin(), faceCountAfter.end(), faces,
                                     [](std::uint32_t have, std::size_t want) { return have > want; });
    return it == faceCountAfter.end() ? steps.size() : static_cast<std::size_t>(it - faceCountAfter.begin()) + 1;
}

RadianceMesh ProgressiveRadianceMesh::extract(std::size_t stepCount) const {
    stepCount = std::min(stepCount, steps.size());
    const std::size_t nv = base.vertexCount();
    std::vector<std::uint32_t> parent(nv);
    for (std::size_t v = 0; v < nv; ++v) parent[v] = static_cast<std::uint32_t>(v);
    std::vector<float> positions = base.positions;
    std::optional<RadianceField> field = base.radiance;
    std::vector<float> normals = base.normals;
    const int row = rowFloats();
    for (std::size_t i = 0; i < stepCount; ++i) {
        const CollapseStep& s = steps[i];
        parent[s.removed] = s.survivor;
        if (kind == CollapseKind::Full) {
            std::copy(s.position, s.position + 3, positions.begin() + 3 * s.survivor);
            if (row > 0) {
                const float* r = survivorRows.data() + i * row;
                std::copy(r, r + 6, field->frame(s.survivor));
                std::copy(r + 6, r + row, field->vertexCoefficients(s.survivor));
                if (!normals.empty()) std::copy(r + 3, r + 6, normals.begin() + 3 * s.survivor);
            }
        }
    }

    RadianceMesh out;
    std::vector<std::uint32_t> newIndex(nv, std::numeric_limits<std::uint32_t>::max());
    std::vector<std::uint32_t> kept;
    for (std::size_t v = 0; v < nv; ++v) {
        if (representative(parent, static_cast<std::uint32_t>(v)) != v) continue;
        newIndex[v] = static_cast<std::uint32_t>(kept.size());
        kept.push_back(static_cast<std::uint32_t>(v));
    }
    for (std::size_t f = 0; f < base.faceCount(); ++f) {
        std::uint32_t t[3];
        for (int k = 0; k < 3; ++k) t[k] = representative(parent, base.faces[3 * f + k]);
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        for (int k = 0; k < 3; ++k) out.faces.push_back(newIndex[t[k]]);
    }
    // Per-vertex arrays follow the kept vertices.
    auto gather = [&](const std::vector<float>& in, std::size_t width, std::vector<float>& to) {
        if (in.empty()) return;
        to.resize(kept.size() * width);
        for (std::size_t i = 0; i < kept.size(); ++i)
            std::copy(in.begin() + kept[i] * width, in.begin() + (kept[i] + 1) * width, to.begin() + i * width);
    };
    gather(positions, 3, out.positions);
    gather(normals, 3, out.normals);
    gather(base.quality, 1, out.quality);
    if (!base.colors.empty()) {
        out.colors.resize(kept.size() * 4);
        for (std::size_t i = 0; i < kept.size(); ++i)
            std::copy(base.colors.begin() + 4 * kept[i], base.colors.begin() + 4 * kept[i] + 4, out.colors.begin() + 4 * i);
    }
    if (field) {
        RadianceField reduced(field->basis, kept.size(), field->reflected);
        gather(field->coefficients, field->coefficientsPerVertex(), reduced.coefficients);
        gather(field->frames, 6, reduced.frames);
        out.radiance = std::move(reduced);
    }
    for (const NamedVertexBlock& block : base.extraBlocks) {
        NamedVertexBlock b = block;
        b.values.clear();
        gather(block.values, block.width, b.values);
        out.extraBlocks.push_back(std::move(b));
    }
    return out;
}

ProgressiveRecorder::ProgressiveRecorder(ProgressiveRadianceMesh& target, const RadianceField* field)
    : target_(target), field_(field) {}

void ProgressiveRecorder::operator()(const CollapseStep& step) {
    target_.steps.push_back(step);
    target_.faceCountAfter.push_back(step.facesAfter);
    const int row = target_.rowFloats();
    if (row > 0) {
        if (!field_) throw std::logic_error("a full collapse of a radiance mesh is recorded without its field");
        const float* frame = field_->frame(step.survivor);
        const float* coefficients = field_->vertexCoefficients(step.survivor);
        target_.survivorRows.insert(target_.survivorRows.end(), frame, frame + 6);
        const std::size_t at = target_.survivorRows.size();
        target_.survivorRows.insert(target_.survivorRows.end(), coefficients,
                                    coefficients + field_->coefficientsPerVertex());
        // The metric may work in the other storage (SH metrics switch to reflected coefficients):
        // rows are kept in the base's storage so that extraction never mixes the two.
        if (field_->reflected != target_.base.radiance->reflected)
            reflectCoefficients(field_->basis, frameFromStored(frame), target_.survivorRows.data() + at,
                                target_.survivorRows.data() + at);
    }
}

namespace {

template <typename T>
void put(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out.append(bytes, sizeof(T));
}

template <typename T>
T take(const char*& p) {
    T value;
    std::memcpy(&value, p, sizeof(T));
    p += sizeof(T);
    return value;
}

}  // namespace

void writeProgressiveMesh(const std::string& path, const std::string& basePath, const ProgressiveRadianceMesh& mesh) {
    AtomicFileSet files;
    stageProgressiveMesh(path, basePath, mesh, files);
    try {
        files.commit();
    } catch (const AtomicFileError& error) {
        throw ProgressiveMeshError(error.what());
    }
}

void stageProgressiveMesh(const std::string& path, const std::string& basePath, const ProgressiveRadianceMesh& mesh,
                          AtomicFileSet& files) {
    const int row = mesh.rowFloats();
    if (mesh.faceCountAfter.size() != mesh.steps.size() || mesh.survivorRows.size() != mesh.steps.size() * row)
        throw ProgressiveMeshError("progressive mesh is inconsistent: " + std::to_string(mesh.steps.size()) +
                                   " steps, " + std::to_string(mesh.faceCountAfter.size()) + " face counts, " +
                                   std::to_string(mesh.survivorRows.size()) + " row floats");
    // Everything that can be refused is refused before a file is written.
    const std::string baseName =
        folderOf(basePath) == folderOf(path) ? basePath.substr(folderOf(basePath).size()) : basePath;
    if (baseName.find_first_of(" \t\r\n") != std::string::npos)
        throw ProgressiveMeshError("the base file name '" + baseName + "' contains white space (the .rpm header "
                                   "cannot hold it): choose a .rpm file name without spaces");
    for (const std::string& target : {path, basePath})
        if (std::string problem = outputPathProblem(target); !problem.empty()) throw ProgressiveMeshError(problem);

    // The base and the records are put in place together (io/atomic_file.h): both or neither.
    const std::string baseTemporary = files.add(basePath);
    writeRadiancePly(baseTemporary, mesh.base);
    const std::string baseBytes = readWholeFile(baseTemporary, "the base just written");

    std::string records;
    records.reserve(mesh.steps.size() * (kFixedRecordBytes + 4 * row));
    for (std::size_t i = 0; i < mesh.steps.size(); ++i) {
        const CollapseStep& s = mesh.steps[i];
        put(records, s.removed);
        put(records, s.survivor);
        put(records, mesh.faceCountAfter[i]);
        for (float x : s.position) put(records, x);
        put(records, s.cost);
        for (int k = 0; k < row; ++k) put(records, mesh.survivorRows[i * row + k]);
    }
    std::ostringstream header;
    header << kMagic << "\n"
           << "format binary_little_endian " << kFormatVersion << "\n"
           << "base " << baseName << "\n"
           << "base_hash " << hashText(fnv1a(baseBytes.data(), baseBytes.size())) << "\n"
           << "collapse_kind " << kindName(mesh.kind) << "\n"
           << "vertex_count " << mesh.base.vertexCount() << "\n"
           << "face_count " << mesh.base.faceCount() << "\n"
           << "steps " << mesh.steps.size() << "\n"
           << "row_floats " << row << "\n"
           << "records_hash " << hashText(fnv1a(records.data(), records.size())) << "\n"
           << "end_header\n";
    const std::string headerText = header.str();
    try {
        writeFileAtomically(files.add(path), {{headerText.data(), headerText.size()}, {records.data(), records.size()}});
    } catch (const AtomicFileError& error) {
        throw ProgressiveMeshError(error.what());
    }
}

ProgressiveRadianceMesh readProgressiveMesh(const std::string& path) {
    std::error_code folderError;
    if (std::filesystem::is_directory(path, folderError))
        throw ProgressiveMeshError("'" + path + "' is a folder, not a .rpm file: choose the .rpm file inside it");
    const std::string contents = readWholeFile(path, "the progressive mesh");
    const std::string endTag = "end_header\n";
    const auto headerEnd = contents.find(endTag);
    if (contents.rfind(std::string(kMagic) + "\n", 0) != 0 || headerEnd == std::string::npos)
        throw ProgressiveMeshError("'" + path + "' is not a radiance progressive mesh (no '" + kMagic +
                                   "' header ending with end_header)");
    std::istringstream header(contents.substr(0, headerEnd));
    std::string line, baseName, kind, baseHash, recordsHash;
    long long vertexCount = -1, faceCount = -1, stepCount = -1, row = -1;
    int version = 0;
    std::getline(header, line);
    const auto number = [&](std::istringstream& words, long long& to) {
        if (!(words >> to) || to < 0)
            throw ProgressiveMeshError("'" + path + "': the header line '" + line + "' needs a count >= 0");
    };
    while (std::getline(header, line)) {
        std::istringstream words(line);
        std::string key;
        words >> key;
        if (key == "format") {
            std::string encoding;
            words >> encoding >> version;
            if (encoding != "binary_little_endian" || version < 1 || version > kFormatVersion)
                throw ProgressiveMeshError("'" + path + "' has an unsupported format line '" + line +
                                           "' (this build reads versions 1 to " + std::to_string(kFormatVersion) + ")");
        } else if (key == "base") words >> baseName;
        else if (key == "base_hash") words >> baseHash;
        else if (key == "records_hash") words >> recordsHash;
        else if (key == "collapse_kind") words >> kind;
        else if (key == "vertex_count") number(words, vertexCount);
        else if (key == "face_count") number(words, faceCount);
        else if (key == "steps") number(words, stepCount);
        else if (key == "row_floats") number(words, row);
        else throw ProgressiveMeshError("'" + path + "': unknown header line '" + line + "'");
    }
    if (version == 0 || baseName.empty() || (kind != "half-edge" && kind != "full") || vertexCount < 0 ||
        faceCount < 0 || stepCount < 0 || row < 0 || (version >= 2 && (baseHash.empty() || recordsHash.empty())))
        throw ProgressiveMeshError("'" + path + "': incomplete header (needs format, base, collapse_kind, "
                                   "vertex_count, face_count, steps, row_floats" +
                                   std::string(version >= 2 ? ", base_hash, records_hash" : "") + ")");
    // Sizes first, without overflow: a header claiming 2^62 steps must not reach a multiplication.
    const std::size_t available = contents.size() - headerEnd - endTag.size();
    if (row > (1 << 20))
        throw ProgressiveMeshError("'" + path + "': row_floats " + std::to_string(row) + " is not a radiance row");
    const std::size_t recordBytes = kFixedRecordBytes + 4 * static_cast<std::size_t>(row);
    if (static_cast<unsigned long long>(stepCount) > available / recordBytes ||
        static_cast<std::size_t>(stepCount) * recordBytes != available)
        throw ProgressiveMeshError("'" + path + "' is truncated or padded: the header claims " +
                                   std::to_string(stepCount) + " steps of " + std::to_string(recordBytes) +
                                   " bytes and the file holds " + std::to_string(available) +
                                   " bytes of records; save the simplification again");
    if (stepCount >= vertexCount && stepCount > 0)
        throw ProgressiveMeshError("'" + path + "' claims " + std::to_string(stepCount) + " collapses of a mesh of " +
                                   std::to_string(vertexCount) + " vertices (each removes one): the file is damaged");
    const char* records = contents.data() + headerEnd + endTag.size();
    if (version >= 2 && hashText(fnv1a(records, available)) != recordsHash)
        throw ProgressiveMeshError("'" + path + "': the collapse records do not match their hash (the file was "
                                   "changed after it was written): save the simplification again");

    ProgressiveRadianceMesh mesh;
    mesh.kind = kind == "full" ? CollapseKind::Full : CollapseKind::HalfEdge;
    const std::string basePath = baseName.front() == '/' ? baseName : folderOf(path) + baseName;
    if (version >= 2) {
        const std::string baseBytes = readWholeFile(basePath, "the base mesh");
        if (hashText(fnv1a(baseBytes.data(), baseBytes.size())) != baseHash)
            throw ProgressiveMeshError("'" + path + "' was recorded on another base than '" + basePath +
                                       "' (its content differs: saved again, reordered, or replaced by a later run): "
                                       "save the simplification again to write both together");
    }
    mesh.base = readRadiancePly(basePath);
    if (static_cast<long long>(mesh.base.vertexCount()) != vertexCount ||
        static_cast<long long>(mesh.base.faceCount()) != faceCount)
        throw ProgressiveMeshError("'" + path + "' was recorded on a mesh of " + std::to_string(vertexCount) +
                                   " vertices and " + std::to_string(faceCount) + " faces but its base '" + basePath +
                                   "' has " + std::to_string(mesh.base.vertexCount()) + " and " +
                                   std::to_string(mesh.base.faceCount()));
    if (row != mesh.rowFloats())
        throw ProgressiveMeshError("'" + path + "': row_floats " + std::to_string(row) + " does not match the base (" +
                                   std::to_string(mesh.rowFloats()) + " expected)");
    const char* p = records;
    std::vector<std::uint8_t> removed(static_cast<std::size_t>(vertexCount), 0);
    std::uint32_t lastFaces = static_cast<std::uint32_t>(faceCount);
    mesh.steps.reserve(static_cast<std::size_t>(stepCount));
    mesh.faceCountAfter.reserve(static_cast<std::size_t>(stepCount));
    mesh.survivorRows.reserve(static_cast<std::size_t>(stepCount) * static_cast<std::size_t>(row));
    for (long long i = 0; i < stepCount; ++i) {
        CollapseStep s;
        s.removed = take<std::uint32_t>(p);
        s.survivor = take<std::uint32_t>(p);
        const std::uint32_t facesAfter = s.facesAfter = take<std::uint32_t>(p);
        for (float& x : s.position) x = take<float>(p);
        s.cost = take<float>(p);
        if (s.removed >= vertexCount || s.survivor >= vertexCount || s.removed == s.survivor || removed[s.removed] ||
            removed[s.survivor] || facesAfter > lastFaces)
            throw ProgressiveMeshError("'" + path + "': step " + std::to_string(i) +
                                       " is inconsistent (vertex out of range, already removed, or face count rising)");
        // Positions the cores cannot compute with (NaN, 1e30) are the file's fault, said here rather
        // than when the replayed level is saved.
        if (!coordinateRangeProblem(s.position, 1).empty())
            throw ProgressiveMeshError("'" + path + "': step " + std::to_string(i) + " moves vertex " +
                                       std::to_string(s.survivor) + " to (" + std::to_string(s.position[0]) + ", " +
                                       std::to_string(s.position[1]) + ", " + std::to_string(s.position[2]) +
                                       "), not a finite position within 1e11: the file is damaged; save the "
                                       "simplification again");
        removed[s.removed] = 1;
        lastFaces = facesAfter;
        mesh.steps.push_back(s);
        mesh.faceCountAfter.push_back(facesAfter);
        for (long long k = 0; k < row; ++k) {
            const float value = take<float>(p);
            if (!std::isfinite(value))
                throw ProgressiveMeshError("'" + path + "': step " + std::to_string(i) + " has a frame or radiance "
                                           "value that is not a finite number: the file is damaged; save the "
                                           "simplification again");
            mesh.survivorRows.push_back(value);
        }
    }
    if (const long long wrong = firstWrongFaceCount(mesh.base, mesh.steps, mesh.faceCountAfter); wrong >= 0)
        throw ProgressiveMeshError("'" + path + "': after step " + std::to_string(wrong) + " the file records " +
                                   std::to_string(mesh.faceCountAfter[std::size_t(wrong)]) +
                                   " faces but replaying the collapses on the base gives another count (a changed "
                                   "record, or a base other than the one recorded on): save the simplification again");
    return mesh;
}

}  // namespace rad
