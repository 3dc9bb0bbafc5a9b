// The host's own name for an operation a core's message names as "{{Name}}" (common/errors/
// host_operations.h): the menu path in MeshLab 2020.09, the MeshSet method in pymeshlab (MeshLab
// 2025.07). Every message a filter or the file format shows passes through forThisHost once.
#pragma once

#include <string>

namespace radml {

// "Filters > Cleaning and Repairing > Remove Zero Area Faces" (MeshLab 2020.09) or
// "MeshSet.meshing_remove_null_faces() (MeshLab's Remove Zero Area Faces)" (pymeshlab); an unknown
// name: "MeshLab's Name".
std::string hostOperationName(const std::string& operation);

// `message` with every "{{Name}}" replaced by hostOperationName(Name).
std::string forThisHost(const std::string& message);

}  // namespace radml
