#include "image/image_io.h"

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_JPEG
#define STBI_ONLY_PNG
#define STBI_ONLY_HDR
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <cstring>
#include <memory>

namespace rad {

Image8 readImage8(const std::string& path) {
    int w = 0, h = 0, channels = 0;
    std::unique_ptr<unsigned char, void (*)(void*)> pixels(stbi_load(path.c_str(), &w, &h, &channels, 3),
                                                           stbi_image_free);
    if (!pixels) {
        const char* reason = stbi_failure_reason();
        throw ImageFileError("cannot read image '" + path + "': " + (reason ? reason : "unknown error"));
    }
    Image8 image(w, h);
    std::memcpy(image.rgb.data(), pixels.get(), image.rgb.size());
    return image;
}

void writePng(const std::string& path, const Image8& image) {
    if (image.rgb.size() != std::size_t(image.width) * image.height * 3)
        throw ImageFileError("cannot write PNG image '" + path + "': the image holds " + std::to_string(image.rgb.size()) +
                             " bytes, not 3 x " + std::to_string(image.width) + " x " + std::to_string(image.height));
    if (image.width <= 0 || image.height <= 0 ||
        !stbi_write_png(path.c_str(), image.width, image.height, 3, image.rgb.data(), image.width * 3))
        throw ImageFileError("cannot write PNG image '" + path + "'");
}

}  // namespace rad
