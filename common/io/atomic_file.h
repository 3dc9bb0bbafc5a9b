// Writing files so that a reader never sees a partial one: everything goes to a temporary file
// beside the destination, is flushed to disk, and is renamed over the destination only when
// complete. A failure or a kill mid-write leaves the old file (or none) and a temporary named
// `<path>.part-<pid>-<n>-<t>`; removeStaleTemporaries() clears those of dead writers, and the unique
// name keeps two processes writing the same path from sharing a temporary.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rad {

struct AtomicFileError : std::runtime_error {
    using std::runtime_error::runtime_error;
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

}  // namespace rad
