// libFuzzer harness for the radiance PLY reader (common/io/radiance_ply.h): every input either loads
// or is refused with RadianceFileError; nothing else may escape, and the sanitizers watch memory and
// undefined behaviour. A file that loads must also be saveable as it is (what the reader accepts, the
// writer accepts: e.g. block metadata) and must read back with the same counts.
// Built by bench/fuzz/CMakeLists.txt (RADIANCE_FUZZ=ON) and run by bench/fuzz_radiance_ply.sh (not in CI).
#include "io/radiance_ply.h"

#include "fuzz_input_file.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string input = fuzz::writeInput("RPLY_FUZZ_TMP", "input.rply", data, size);
    rad::RadianceMesh mesh;
    try {
        mesh = rad::readRadiancePly(input);
    } catch (const rad::RadianceFileError& e) {
        // A refusal is a sentence naming the file.
        if (std::strncmp(e.what(), "cannot load '", 13) != 0) std::abort();
        return 0;
    }
    const std::string problem = rad::validateRadianceMesh(mesh);
    if (!problem.empty()) {
        std::fprintf(stderr, "loaded a mesh the writer refuses: %s\n", problem.c_str());
        std::abort();
    }
    const std::string copy = fuzz::workFolder("RPLY_FUZZ_TMP") + "/copy.rply";
    rad::writeRadiancePly(copy, mesh);
    const rad::RadianceMesh back = rad::readRadiancePly(copy);
    if (back.vertexCount() != mesh.vertexCount() || back.faces != mesh.faces ||
        back.extraBlocks.size() != mesh.extraBlocks.size() || back.radiance.has_value() != mesh.radiance.has_value()) {
        std::fprintf(stderr, "the saved copy reads back differently\n");
        std::abort();
    }
    for (std::size_t b = 0; b < mesh.extraBlocks.size(); ++b)
        if (back.extraBlocks[b].metadata != mesh.extraBlocks[b].metadata ||
            std::memcmp(back.extraBlocks[b].values.data(), mesh.extraBlocks[b].values.data(),
                        mesh.extraBlocks[b].values.size() * sizeof(float)) != 0) {
            std::fprintf(stderr, "block %zu changed through a save\n", b);
            std::abort();
        }
    return 0;
}
