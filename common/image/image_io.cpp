#include "image/image_io.h"

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_JPEG
#define STBI_ONLY_PNG
#define STBI_ONLY_HDR
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include "image/parallel_png_encoder.h"

#include <cstdio>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>

namespace rad {

namespace {

// The file the user knows: a temporary `<path>.part-<pid>-<n>-<t>` (io/atomic_file.h) is named by
// its destination in messages.
std::string shownName(const std::string& path) {
    const std::size_t part = path.rfind(".part-");
    return part == std::string::npos ? path : path.substr(0, part);
}

// Every step checked (the stb writer ignores fwrite's result: a full disk or a file-size limit
// gave a truncated map reported as written); a failed file is removed.
bool outOfSpace(int err) {
#ifdef EDQUOT
    if (err == EDQUOT) return true;
#endif
    return err == ENOSPC || err == EFBIG;
}

void writeBytes(const std::string& path, const std::vector<unsigned char>& bytes, const char* what) {
    const auto fail = [&](int err) {
        std::error_code ignored;
        if (std::filesystem::is_regular_file(path, ignored)) std::remove(path.c_str());  // never a device
        throw ImageFileError("cannot write " + std::string(what) + " '" + shownName(path) + "': " + std::strerror(err) +
                             (outOfSpace(err)
                                  ? " (the disk is full or the file exceeds a size limit): free space or choose "
                                    "another folder"
                                  : ": check that the folder exists and is writable") +
                             "; nothing was written");
    };
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) fail(errno);
    if (std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size() || std::fflush(file) != 0) {
        const int err = errno;
        std::fclose(file);
        fail(err);
    }
    if (std::fclose(file) != 0) fail(errno);
}

}  // namespace

void writePng(const std::string& path, const Image8& image) {
    if (image.rgb.size() != std::size_t(image.width) * image.height * 3)
        throw ImageFileError("cannot write PNG image '" + shownName(path) + "': the image holds " +
                             std::to_string(image.rgb.size()) + " bytes, not 3 x " + std::to_string(image.width) +
                             " x " + std::to_string(image.height));
    writeBytes(path, encodePng(image), "PNG image");
}

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

void readImageSize(const std::string& path, int& width, int& height) {
    int channels = 0;
    if (!stbi_info(path.c_str(), &width, &height, &channels)) {
        const char* reason = stbi_failure_reason();
        throw ImageFileError("cannot read image '" + path + "': " + (reason ? reason : "unknown error"));
    }
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

void writePng16(const std::string& path, int width, int height, int channels, const std::uint16_t* samples) {
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || !samples)
        throw ImageFileError("cannot write 16-bit PNG image '" + path + "': bad size " + std::to_string(width) + " x " +
                             std::to_string(height) + " x " + std::to_string(channels) + " (1 to 4 channels)");
    // 16-bit maps compress poorly anyway: the fastest zlib level, run lengths only, on every
    // thread (image/parallel_png_encoder.h).
    std::vector<unsigned char> bytes;
    try {
        bytes = encodePngParallel(samples, width, height, channels, 16, 1, PngCompression::RunLength);
    } catch (const std::exception& e) {
        throw ImageFileError("cannot write 16-bit PNG image '" + path + "': " + e.what());
    }
    writeBytes(path, bytes, "16-bit PNG image");
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
