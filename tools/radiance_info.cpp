// radiance_info FILE.rply: prints what a radiance PLY file holds (counts, basis, memory, value
// ranges), or the reader's error message with exit status 1.
#include "io/radiance_ply.h"

#include <algorithm>
#include <cstdio>
#include <limits>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s FILE.rply\n", argv[0]);
        return 2;
    }
    try {
        const rad::RadianceMesh mesh = rad::readRadiancePly(argv[1]);
        std::printf("%s: %zu vertices, %zu triangles%s%s%s\n", argv[1], mesh.vertexCount(), mesh.faceCount(),
                    mesh.normals.empty() ? "" : ", normals", mesh.colors.empty() ? "" : ", colours",
                    mesh.quality.empty() ? "" : ", quality");
        if (!mesh.radiance) {
            std::printf("  no radiance data\n");
        } else {
            const rad::RadianceField& field = *mesh.radiance;
            float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
            for (float c : field.coefficients) {
                lo = std::min(lo, c);
                hi = std::max(hi, c);
            }
            std::printf("  radiance %s%s: %d coefficients per vertex (%d per channel), %.2f MB of coefficients\n",
                        field.basis.name().c_str(), field.reflected ? " (reflected)" : "", field.coefficientsPerVertex(),
                        field.coefficientsPerChannel(), field.coefficients.size() * sizeof(float) / 1e6);
            std::printf("  coefficient range [%g, %g]\n", lo, hi);
        }
        // Blocks are independent of radiance (e.g. PRT transfer vectors on a mesh without RF).
        for (const auto& block : mesh.extraBlocks) {
            std::printf("  extra block %s: %d floats per vertex", block.prefix.c_str(), block.width);
            for (const auto& kv : block.metadata) std::printf(", %s=%s", kv.first.c_str(), kv.second.c_str());
            std::printf("\n");
        }
        for (const auto& skipped : mesh.skippedOnRead) std::printf("  not loaded: %s\n", skipped.c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
}
