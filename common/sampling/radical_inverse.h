// Van der Corput radical inverse in base 2, the second coordinate of the Hammersley point sets that
// the PRT transfer, the irradiance grid and its reference images draw their hemisphere directions
// from (each maps the pair ((i + 0.5) / n, radicalInverse2(i)) to its own distribution).
#pragma once
#include <cstdint>

namespace rad {

// The bits of i mirrored about the binary point: 1 -> 0.5, 2 -> 0.25, 3 -> 0.75, 6 -> 0.375.
inline double radicalInverse2(std::uint32_t i) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
    i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
    i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
    i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
    return i * (1.0 / 4294967296.0);
}

}  // namespace rad
