// The papers our filters implement, as their help texts cite them (docs/references.md lists them).
#pragma once

namespace radml {

inline constexpr const char* kCiteVanhoey2015 =
    "<br><br>Radiance functions as in <i>K. Vanhoey, B. Sauvage, P. Kraemer, F. Larue, J.-M. Dischler</i>, "
    "<b>\"Simplification of meshes with digitized radiance\"</b>, The Visual Computer 31 (2015).";

inline constexpr const char* kCiteGranier2007WeberStamminger =
    "<br><br>Normal maps from the full scan onto the simplified mesh, holes filled by diffusion: <i>X. Granier, "
    "R. Pacanowski, C. Schlick</i>, <b>\"Managing Geometry Complexity for Illumination Computation of Cultural "
    "Heritage Scenes\"</b> (2007). LEAN covariances relative to the averaged normal, level 0 omitted: <i>T. Weber, "
    "M. Stamminger</i>, <b>\"Stateless Level of Detail Lighting for Automotive Visualization\"</b> (Alg. 2-4, "
    "sec. 3.5), after <i>M. Olano, D. Baker</i>, \"LEAN Mapping\", I3D 2010.";

inline constexpr const char* kCiteGranier2007Lindstrom2000 =
    "<br><br>Out-of-core simplification and normal maps from the streamed scan: <i>X. Granier, R. Pacanowski, "
    "C. Schlick</i>, <b>\"Managing Geometry Complexity for Illumination Computation of Cultural Heritage "
    "Scenes\"</b> (2007). Vertex clustering with quadrics: <i>P. Lindstrom</i>, <b>\"Out-of-Core Simplification "
    "of Large Polygonal Models\"</b>, SIGGRAPH 2000.";
inline constexpr const char* kCiteGranier2007Ivg =
    "<br><br>Irradiance vector grid: <i>X. Granier, R. Pacanowski, C. Schlick</i>, <b>\"Managing Geometry "
    "Complexity for Illumination Computation of Cultural Heritage Scenes\"</b> (2007), after the irradiance "
    "vector of <i>J. Arvo</i>, \"The Irradiance Jacobian for Partially Occluded Polyhedral Sources\", SIGGRAPH "
    "1994. Environment map as lights: <i>P. Debevec</i>, \"A Median Cut Algorithm for Light Probe Sampling\" (2005).";

inline constexpr const char* kCiteMikkelsen2008 =
    "<br><br>Tangent space: <i>M. S. Mikkelsen</i>, <b>\"Simulation of wrinkled surfaces revisited\"</b>, "
    "MSc thesis, University of Copenhagen (2008) (MikkTSpace).";

inline constexpr const char* kCiteSloan2002Krivanek2004 =
    "<br><br>Transfer vectors: <i>P.-P. Sloan, J. Kautz, J. Snyder</i>, <b>\"Precomputed radiance transfer for "
    "real-time rendering in dynamic, low-frequency lighting environments\"</b>, SIGGRAPH 2002. Adaptive "
    "subdivision: <i>J. Křivánek, S. Pattanaik, J. Žára</i>, <b>\"Adaptive Mesh Subdivision for "
    "Precomputed Radiance Transfer\"</b>, SCCG 2004.";

inline constexpr const char* kCiteLimper2013WeberStamminger =
    "<br><br>POP buffer: <i>J. Limper, Y. Jung, J. Behr, M. Alexa</i>, <b>\"The POP Buffer: Rapid Progressive "
    "Clustering by Geometry Quantization\"</b>, Computer Graphics Forum 32(7) (Pacific Graphics 2013). "
    "Texture-coordinate correction: <i>T. Weber, M. Stamminger</i>, <b>\"Stateless Level of Detail Lighting for "
    "Automotive Visualization\"</b> (eq. 1-3, Alg. 1).";

}  // namespace radml
