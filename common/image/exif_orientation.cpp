#include "image/exif_orientation.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

namespace rad {

namespace {

// The orientation tag of a TIFF structure (an EXIF segment's payload after "Exif\0\0").
int orientationOfTiff(const unsigned char* t, std::size_t size) {
    if (size < 8) return 1;
    const bool little = t[0] == 'I' && t[1] == 'I';
    if (!little && !(t[0] == 'M' && t[1] == 'M')) return 1;
    const auto u16 = [&](std::size_t at) -> unsigned {
        return little ? unsigned(t[at]) | unsigned(t[at + 1]) << 8 : unsigned(t[at]) << 8 | unsigned(t[at + 1]);
    };
    const auto u32 = [&](std::size_t at) -> std::uint32_t {
        return little ? std::uint32_t(u16(at)) | std::uint32_t(u16(at + 2)) << 16
                      : std::uint32_t(u16(at)) << 16 | std::uint32_t(u16(at + 2));
    };
    if (u16(2) != 42) return 1;
    const std::uint32_t ifd = u32(4);
    if (ifd + 2 > size) return 1;
    const unsigned entries = u16(ifd);
    for (unsigned i = 0; i < entries; ++i) {
        const std::size_t entry = ifd + 2 + 12 * std::size_t(i);
        if (entry + 12 > size) return 1;
        if (u16(entry) == 0x0112 && u16(entry + 2) == 3) {  // Orientation, SHORT: the value is inline
            const unsigned value = u16(entry + 8);
            return value >= 1 && value <= 8 ? int(value) : 1;
        }
    }
    return 1;
}

}  // namespace

int exifOrientationOfJpeg(const unsigned char* b, std::size_t size) {
    if (size < 4 || b[0] != 0xFF || b[1] != 0xD8) return 1;
    std::size_t at = 2;
    while (at + 4 <= size && b[at] == 0xFF) {
        const unsigned marker = b[at + 1];
        if (marker == 0xD9 || marker == 0xDA) break;  // end of image, start of scan: no more metadata
        const std::size_t length = std::size_t(b[at + 2]) << 8 | b[at + 3];
        if (length < 2 || at + 2 + length > size) break;
        const unsigned char* payload = b + at + 4;
        if (marker == 0xE1 && length >= 8 && std::memcmp(payload, "Exif\0\0", 6) == 0)
            return orientationOfTiff(payload + 6, length - 2 - 6);
        at += 2 + length;
    }
    return 1;
}

int readExifOrientation(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return 1;
    // The EXIF segment comes first in practice; 256 KB covers it and any APP0/ICC segment before.
    std::vector<unsigned char> head(256 * 1024);
    in.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
    return exifOrientationOfJpeg(head.data(), std::size_t(in.gcount()));
}

Image8 applyExifOrientation(const Image8& stored, int orientation) {
    if (orientation < 2 || orientation > 8) return stored;
    const int w = stored.width, h = stored.height;
    const bool swap = orientationSwapsAxes(orientation);
    Image8 out(swap ? h : w, swap ? w : h);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            // The stored pixel (sx, sy) shown at (x, y).
            int sx = x, sy = y;
            switch (orientation) {
                case 2: sx = w - 1 - x; break;
                case 3: sx = w - 1 - x; sy = h - 1 - y; break;
                case 4: sy = h - 1 - y; break;
                case 5: sx = y; sy = x; break;
                case 6: sx = y; sy = h - 1 - x; break;
                case 7: sx = w - 1 - y; sy = h - 1 - x; break;
                case 8: sx = w - 1 - y; sy = x; break;
            }
            const std::uint8_t* p = stored.rgb.data() + (std::size_t(sy) * w + sx) * 3;
            std::uint8_t* q = out.pixel(x, y);
            q[0] = p[0];
            q[1] = p[1];
            q[2] = p[2];
        }
    return out;
}

}  // namespace rad
