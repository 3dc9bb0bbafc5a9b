#include "host_operations.h"

#include "meshlab_host.h"

#include "errors/host_operations.h"

namespace radml {

namespace {

struct HostOperation {
    const char* name;      // MeshLab's filter name, as the cores write it
    const char* menuPath;  // MeshLab 2020.09
    const char* method;    // pymeshlab's MeshSet method (MeshLab 2025.07)
};

constexpr HostOperation kOperations[] = {
    {"Compute normals for point sets", "Filters > Normals, Curvatures and Orientation > Compute normals for point sets",
     "compute_normal_for_point_clouds"},
    {"Re-Compute Vertex Normals", "Filters > Normals, Curvatures and Orientation > Re-Compute Vertex Normals",
     "compute_normal_per_vertex"},
    {"Transform: Scale, Normalize", "Filters > Normals, Curvatures and Orientation > Transform: Scale, Normalize",
     "compute_matrix_from_scaling_or_normalization"},
    {"Transform: Translate, Center, set Origin",
     "Filters > Normals, Curvatures and Orientation > Transform: Translate, Center, set Origin",
     "compute_matrix_from_translation"},
    {"Remove Zero Area Faces", "Filters > Cleaning and Repairing > Remove Zero Area Faces", "meshing_remove_null_faces"},
    {"Remove Unreferenced Vertices", "Filters > Cleaning and Repairing > Remove Unreferenced Vertices",
     "meshing_remove_unreferenced_vertices"},
    {"Remove Duplicate Vertices", "Filters > Cleaning and Repairing > Remove Duplicate Vertices",
     "meshing_remove_duplicate_vertices"},
    {"Repair non Manifold Edges", "Filters > Cleaning and Repairing > Repair non Manifold Edges",
     "meshing_repair_non_manifold_edges"},
    {"Turn into a Pure-Triangular mesh", "Filters > Polygonal and Quad Mesh > Turn into a Pure-Triangular mesh",
     "meshing_poly_to_tri"},
    {"Import Raster", "File > Import Raster", "load_new_raster"},
};

}  // namespace

std::string hostOperationName(const std::string& operation) {
    for (const HostOperation& o : kOperations) {
        if (operation != o.name) continue;
        // pymeshlab's method, and MeshLab's name that its documentation and users know too.
        if (kMeshLabHostYear >= 2025) return std::string("MeshSet.") + o.method + "() (MeshLab's " + o.name + ")";
        return o.menuPath;
    }
    return "MeshLab's " + operation;
}

std::string forThisHost(const std::string& message) { return rad::expandHostOperations(message, hostOperationName); }

}  // namespace radml
