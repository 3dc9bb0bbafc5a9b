#include "cameras/camera_file.h"

#include "cameras/colmap_model_reader.h"
#include "cameras/metashape_xml_reader.h"
#include "cameras/nerfstudio_transforms_reader.h"

#include <fstream>
#include <sys/stat.h>

namespace rad {

namespace {

const char* const kFormats =
    "a COLMAP model folder (cameras.bin + images.bin, or cameras.txt + images.txt) or one of its files, an Agisoft "
    "Metashape camera XML (File > Export > Export Cameras, Agisoft XML), or a nerfstudio transforms.json";

std::string fileName(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string folderOf(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

// The first character that is not white space or a UTF-8 byte-order mark (0 for none).
char firstSignificantCharacter(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char c = 0;
    while (in.get(c))
        if (!(c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\xEF' || c == '\xBB' || c == '\xBF')) return c;
    return 0;
}

}  // namespace

CameraImport readCameraFile(const std::string& path) {
    struct stat st;
    if (path.empty() || ::stat(path.c_str(), &st) != 0)
        throw CameraFileError("camera file '" + path + "' does not exist; give " + kFormats);
    if (S_ISDIR(st.st_mode)) return readColmapModel(path);
    const std::string name = fileName(path);
    for (const char* colmapFile : {"cameras.bin", "images.bin", "points3D.bin", "rigs.bin", "frames.bin", "cameras.txt",
                                   "images.txt", "points3D.txt", "rigs.txt", "frames.txt"})
        if (name == colmapFile) return readColmapModel(folderOf(path));
    const char first = firstSignificantCharacter(path);
    if (first == '<') return readMetashapeXml(path);
    if (first == '{') return readNerfstudioTransforms(path);
    throw CameraFileError("'" + path + "' is not a camera file this import reads; give " + kFormats);
}

}  // namespace rad
