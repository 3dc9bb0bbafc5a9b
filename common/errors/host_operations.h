// Remedies that are an operation of the host application. A core's message names such an operation
// by MeshLab's filter name between double braces, "{{Remove Zero Area Faces}}", and never by a menu
// path: the cores also serve the command-line tools and pymeshlab, whose users have no menus. Each
// host names the operation its own way when it shows the message (plugins_shared/host_operations:
// MeshLab's menu path, pymeshlab's MeshSet method); other programs call plainHostOperations.
#pragma once

#include <functional>
#include <string>

namespace rad {

// Every "{{Name}}" of `message` replaced by name("Name"); text outside markers is kept as it is.
std::string expandHostOperations(const std::string& message, const std::function<std::string(const std::string&)>& name);

// The form for programs that are not MeshLab: "{{Name}}" becomes "MeshLab's Name".
std::string plainHostOperations(const std::string& message);

}  // namespace rad
