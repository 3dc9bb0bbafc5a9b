// libFuzzer harness for the irradiance vector grid reader (common/lighting/irradiance_vector_grid.h):
// every input either loads or is refused with IrradianceVectorGridError; nothing else may escape
// (std::bad_alloc included: a header announcing a grid the machine cannot hold is refused first), and
// the sanitizers watch memory and undefined behaviour. A grid that loads must validate, interpolate
// and write back. Built by bench/fuzz/CMakeLists.txt (RADIANCE_FUZZ=ON) and run by bench/fuzz_readers.sh (not in CI).
#include "lighting/irradiance_vector_grid.h"

#include "fuzz_input_file.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string input = fuzz::writeInput("IVG_FUZZ_DIR", "input.ivg", data, size);
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
    rad::writeIrradianceVectorGrid(fuzz::workFolder("IVG_FUZZ_DIR") + "/copy.ivg", grid);
    return 0;
}
