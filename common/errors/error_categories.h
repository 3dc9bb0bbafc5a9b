// The error contract of the cores: every error a core throws belongs to one category, named for what
// the caller can do about it: InputError (fix the mesh, a parameter or the scene; a
// std::invalid_argument), FileError (another file, path or folder), ResourceError (retry smaller or
// elsewhere), InternalError (a bug to report), plus OperationCancelled and std::bad_alloc. Module
// errors derive from a category: a caller that only reports catches the category, one that can do
// more catches the module error. Cores never name a MeshLab menu; the plugins and tools map each
// category to the user's message once.
// Details: docs/architecture.md, "The error contract".
#pragma once

#include <stdexcept>

namespace rad {

struct InputError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

struct FileError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct ResourceError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct InternalError : std::logic_error {
    using std::logic_error::logic_error;
};

}  // namespace rad
