// libFuzzer harness for the irradiance vector grid reader (common/lighting/irradiance_vector_grid.h):
// every input either loads or is refused with IrradianceVectorGridError; nothing else may escape
// (std::bad_alloc included: a header announcing a grid the machine cannot hold is refused first), and
// the sanitizers watch memory and undefined behaviour. A grid that loads must validate, interpolate
// and write back. Built and run by bench/fuzz_readers.sh (not part of CMake or CI).
#include "lighting/irradiance_vector_grid.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

bool writeFile(const std::string& path, const std::uint8_t* data, std::size_t size) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return false;
    const bool ok = std::fwrite(data, 1, size, f) == size;
    return std::fclose(f) == 0 && ok;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const char* folder = std::getenv("IVG_FUZZ_DIR");
    if (!folder) std::abort();
    const std::string input = std::string(folder) + "/input.ivg";
    if (!writeFile(input, data, size)) std::abort();
    rad::IrradianceVectorGrid grid;
    try {
        grid = rad::readIrradianceVectorGrid(input);
    } catch (const rad::IrradianceVectorGridError&) {
        return 0;
    }
    grid.validate();  // throws (and so aborts the run) on a grid the reader should have refused
    const float point[3] = {grid.origin[0] + 0.5f * grid.cellSize[0], grid.origin[1], grid.origin[2]};
    const float normal[3] = {0.0f, 0.6f, 0.8f};
    float out[9];
    rad::interpolateIrradianceVector(grid, point, normal, out);  // reads every corner it touches (ASan)
    rad::writeIrradianceVectorGrid(std::string(folder) + "/copy.ivg", grid);
    return 0;
}
