// The error contract of the cores: every error a core throws belongs to one category, named for what
// the caller can do about it. Module errors (FitError, RadianceFileError...) derive from a category, so
// a caller that only needs to decide what to tell the user catches the category; one that can do more
// (a reader trying another format) catches the module error.
//
//   InputError        the mesh, a parameter or the scene is wrong: the message says what and how to fix it
//                     (a std::invalid_argument, as the cores' plain argument checks throw);
//   FileError         a file could not be read or written, or its content is not what it must be: the
//                     message names the file and what to do (another file, path or folder);
//   ResourceError     the machine could not provide something (a ray-tracing device, a buffer size):
//                     retry smaller or elsewhere;
//   InternalError     a broken invariant: a bug to report;
//   OperationCancelled (progress/progress_callback.h) the caller asked to stop;
//   std::bad_alloc    out of memory (the standard's own).
//
// A core never names a MeshLab menu to reach a category's remedy; the plugin layer maps categories to
// the user's message once (plugins_shared/filter_errors.cpp), the command-line tools once
// (tools/command_line.h).
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
