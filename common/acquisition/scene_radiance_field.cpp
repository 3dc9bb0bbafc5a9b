#include "acquisition/scene_radiance_field.h"

#include "radiance/radiance_frame.h"
#include "radiance/radiance_projection.h"

#include <omp.h>


namespace rad {

RadianceField sceneRadianceField(const VirtualScene& scene, const BasisSpec& basis, bool reflected,
                                 const ProgressCallback& progress) {
    const TriangleMesh& mesh = scene.mesh();
    const std::size_t n = mesh.vertexCount();
    RadianceField field(basis, n, reflected);
    const FunctionProjector projector(basis);
    LoopProgress loop(progress, "projecting the scene's radiance onto the basis", n);
#pragma omp parallel for schedule(dynamic, 256)
    for (long v = 0; v < static_cast<long>(n); ++v) {
        if (loop.stopRequested()) continue;
        const Eigen::Vector3d p(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
        const Eigen::Vector3d normal =
            Eigen::Vector3d(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]).normalized();
        storeFrame(frameFromNormal(normal), field.frame(static_cast<std::size_t>(v)));
        projector.projectIntoField(field, static_cast<std::size_t>(v),
                                   [&](const Eigen::Vector3d& w) { return scene.radiance(p, normal, w); });
        loop.itemDone(omp_get_thread_num() == 0);
    }
    loop.finish();
    return field;
}

}  // namespace rad
