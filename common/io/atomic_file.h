// Writing files so that a reader never sees a partial one: everything goes to a temporary file
// beside the destination, is flushed to disk, and is renamed over the destination only when
// complete. A failure or a kill mid-write leaves the old file (or none) and a temporary named
// `<path>.part-<pid>-<n>-<t>`; removeStaleTemporaries() clears those of dead writers, and the unique
// name keeps two processes writing the same path from sharing a temporary.
#pragma once

#include "errors/error_categories.h"

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rad {

struct AtomicFileError : FileError {
    using FileError::FileError;
};

// `<path>.part-<pid>-<n>-<t>`: unique per process and call.
std::string uniqueTemporaryPath(const std::string& path);

// Removes the temporaries of `path` whose writer process no longer exists (checked on this machine;
// a live writer's file is never touched; nothing is removed on Windows).
void removeStaleTemporaries(const std::string& path);

// Renames `from` over `to` (replacing it); false with errno set on failure.
bool replaceFile(const std::string& from, const std::string& to);

// Writes the concatenation of `pieces` (pointer, byte count) to `path` atomically, as described
// above. Throws AtomicFileError naming the path, the cause and a fix; nothing is left behind.
void writeFileAtomically(const std::string& path, const std::vector<std::pair<const void*, std::size_t>>& pieces);

// Sentence naming why files cannot be written at `path` (a file to create), with the fix, or empty:
// its folder missing, a file where the folder should be, `path` itself a folder, the folder not
// writable. Checked before any work so that a refusal comes first, not after the computation.
std::string outputPathProblem(const std::string& path);

// Several files written as one (a bake's maps and description, a progressive mesh and its base):
// add() gives each destination a unique temporary (uniqueTemporaryPath) to write; commit() puts
// them all in place or none: the destinations it already replaced get their old contents back
// (kept as hard links, or copies where links are not possible) and new ones are removed when a
// later rename fails. Without commit (an error, a cancel) the destructor removes every temporary.
// A process killed inside commit() can leave some files new and some old, each one complete, and
// `.part-<pid>-...` files that removeStaleTemporaries() clears.
class AtomicFileSet {
public:
    AtomicFileSet() = default;
    AtomicFileSet(const AtomicFileSet&) = delete;
    AtomicFileSet& operator=(const AtomicFileSet&) = delete;
    ~AtomicFileSet();

    // The temporary to write `finalPath`'s contents to (stale temporaries of dead writers of that
    // path are removed first).
    std::string add(const std::string& finalPath);
    // Throws AtomicFileError naming the file that could not be put in place, the cause and a fix;
    // then every destination is as it was before.
    void commit();

private:
    std::vector<std::string> finals_, temporaries_;
    bool committed_ = false;
};

}  // namespace rad
