// The papers our filters implement, as their help texts cite them (docs/references.md lists them).
#pragma once

namespace radml {

inline constexpr const char* kCiteVanhoey2015 =
    "<br><br>Radiance functions as in <i>K. Vanhoey, B. Sauvage, P. Kraemer, F. Larue, J.-M. Dischler</i>, "
    "<b>\"Simplification of meshes with digitized radiance\"</b>, The Visual Computer 31 (2015).";

}  // namespace radml
