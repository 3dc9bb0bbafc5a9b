// libFuzzer harness for the progressive-mesh reader (common/simplify/progressive_mesh.h): the input is
// a .rpm file beside a fixed base (written once by bench/fuzz/make_reader_seeds.cpp as base.rply
// in the fuzzing folder); every input either loads or is refused with ProgressiveMeshError (or the
// base's RadianceFileError); nothing else may escape, and the sanitizers watch memory and undefined
// behaviour. A file that loads must replay every level without error and with face counts that
// never rise. Built by bench/fuzz/CMakeLists.txt (RADIANCE_FUZZ=ON) and run by bench/fuzz_readers.sh (not in CI).
#include "io/radiance_ply.h"
#include "simplify/progressive_mesh.h"

#include "fuzz_input_file.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (!std::getenv("RPM_FUZZ_DIR")) std::abort();  // the folder holding base.rply (the script sets it)
    const std::string input = fuzz::writeInput("RPM_FUZZ_DIR", "input.rpm", data, size);
    rad::ProgressiveRadianceMesh mesh;
    try {
        mesh = rad::readProgressiveMesh(input);
    } catch (const rad::ProgressiveMeshError&) {
        return 0;
    } catch (const rad::RadianceFileError&) {
        return 0;  // the header named another base file, which is not a radiance PLY
    }
    std::size_t last = mesh.baseFaceCount();
    for (std::size_t k = 0; k <= mesh.steps.size(); k += 1 + mesh.steps.size() / 8) {
        const rad::RadianceMesh level = mesh.extract(k);
        if (level.faceCount() > last || !rad::validateRadianceMesh(level).empty()) {
            std::fprintf(stderr, "level %zu of an accepted file is wrong\n", k);
            std::abort();
        }
        last = level.faceCount();
    }
    return 0;
}
