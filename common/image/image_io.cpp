#include "image/image_io.h"

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_JPEG
#define STBI_ONLY_PNG
#define STBI_ONLY_HDR
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cerrno>
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

std::vector<unsigned char> encodePng(const Image8& image) {
    if (image.width <= 0 || image.height <= 0 || image.rgb.size() != std::size_t(image.width) * image.height * 3)
        throw ImageFileError("cannot encode a PNG image of " + std::to_string(image.width) + " x " +
                             std::to_string(image.height) + " texels from " + std::to_string(image.rgb.size()) + " bytes");
    std::vector<unsigned char> bytes;
    const auto append = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<unsigned char>*>(context);
        out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
    };
    if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.rgb.data(), image.width * 3))
        throw ImageFileError("cannot encode a PNG image in memory");
    return bytes;
}

namespace {

// libpng reports errors by longjmp; this keeps the message for the exception thrown afterwards.
struct PngErrorState {
    char message[256] = "";
};

void pngError(png_structp png, png_const_charp message) {
    auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
    std::snprintf(state->message, sizeof state->message, "%s", message ? message : "libpng error");
    png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {}

// The libpng part, free of C++ objects with destructors (longjmp skips them). `rows` holds the
// big-endian samples. Returns an empty string or the reason of the failure.
std::string writePng16Rows(std::FILE* file, int width, int height, int colorType, png_bytep* rows) {
    PngErrorState state;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, pngError, pngWarning);
    if (!png) return "libpng cannot create a writer";
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        return "libpng cannot create a writer";
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return state.message;
    }
    png_init_io(png, file);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 16, colorType, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    // Normal maps compress poorly anyway: the fastest zlib level and one fixed row filter ("up":
    // smooth maps are alike from row to row) instead of libpng's per-row trial of all five, which
    // took 4 s for a 4096 x 4096 map; now about 1 s, files ~10 % larger.
    png_set_compression_level(png, 1);
    png_set_filter(png, 0, PNG_FILTER_UP);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return "";
}

}  // namespace

void writePng16(const std::string& path, int width, int height, int channels, const std::uint16_t* samples) {
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || !samples)
        throw ImageFileError("cannot write 16-bit PNG image '" + path + "': bad size " + std::to_string(width) + " x " +
                             std::to_string(height) + " x " + std::to_string(channels) + " (1 to 4 channels)");
    const int colorType = channels == 1   ? PNG_COLOR_TYPE_GRAY
                          : channels == 2 ? PNG_COLOR_TYPE_GRAY_ALPHA
                          : channels == 3 ? PNG_COLOR_TYPE_RGB
                                          : PNG_COLOR_TYPE_RGBA;
    // PNG stores 16-bit samples big-endian.
    const std::size_t rowBytes = std::size_t(width) * channels * 2;
    std::vector<png_byte> bytes(rowBytes * height);
    const std::size_t count = std::size_t(width) * height * channels;
    for (std::size_t i = 0; i < count; ++i) {
        bytes[2 * i] = png_byte(samples[i] >> 8);
        bytes[2 * i + 1] = png_byte(samples[i] & 0xff);
    }
    std::vector<png_bytep> rows(static_cast<std::size_t>(height));
    for (int r = 0; r < height; ++r) rows[std::size_t(r)] = bytes.data() + rowBytes * r;

    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) throw ImageFileError("cannot write 16-bit PNG image '" + path + "': " + std::strerror(errno));
    std::string problem = writePng16Rows(file, width, height, colorType, rows.data());
    if (std::fclose(file) != 0 && problem.empty()) problem = std::strerror(errno);
    if (!problem.empty()) {
        std::remove(path.c_str());
        throw ImageFileError("cannot write 16-bit PNG image '" + path + "': " + problem);
    }
}

std::vector<std::uint16_t> readPng16(const std::string& path, int& width, int& height, int& channels) {
    int w = 0, h = 0, c = 0;
    std::unique_ptr<stbi_us, void (*)(void*)> pixels(stbi_load_16(path.c_str(), &w, &h, &c, 0), stbi_image_free);
    if (!pixels) {
        const char* reason = stbi_failure_reason();
        throw ImageFileError("cannot read image '" + path + "': " + (reason ? reason : "unknown error"));
    }
    width = w;
    height = h;
    channels = c;
    return std::vector<std::uint16_t>(pixels.get(), pixels.get() + std::size_t(w) * h * c);
}

}  // namespace rad
