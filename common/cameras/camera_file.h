// Which tool wrote a camera file, and its reader: a COLMAP model folder (cameras.bin + images.bin,
// or cameras.txt + images.txt) or one of its files, a Metashape camera XML, a nerfstudio
// transforms.json. The format is recognised by the files' contents and names, not by the caller.
#pragma once

#include "cameras/imported_camera.h"

#include <string>

namespace rad {

// Reads `path`; every camera is validated. Throws CameraFileError (what, where, what to do) for a
// path that is missing, of another format, or holds anything the import cannot use.
CameraImport readCameraFile(const std::string& path);

}  // namespace rad
