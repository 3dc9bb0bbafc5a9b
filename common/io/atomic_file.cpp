#include "io/atomic_file.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

#ifdef _WIN32
#include <io.h>
#include <process.h>
#include <windows.h>
#else
#include <csignal>
#include <sys/types.h>
#include <unistd.h>
#endif

namespace rad {
namespace {

bool allDigits(const std::string& s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

long currentProcessId() {
#ifdef _WIN32
    return static_cast<long>(_getpid());
#else
    return static_cast<long>(getpid());
#endif
}

struct FileCloser {
    void operator()(std::FILE* f) const {
        if (f) std::fclose(f);
    }
};

}  // namespace

std::string uniqueTemporaryPath(const std::string& path) {
    static std::atomic<unsigned> counter{0};
    const auto ticks = std::chrono::steady_clock::now().time_since_epoch().count();
    return path + ".part-" + std::to_string(currentProcessId()) + "-" + std::to_string(counter++) + "-" +
           std::to_string(ticks % 1000000);
}

void removeStaleTemporaries(const std::string& path) {
#ifndef _WIN32
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path target(path);
    const std::string prefix = target.filename().string() + ".part-";
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    fs::directory_iterator it(folder, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
        // Exactly <pid>-<n>-<t>, decimal: anything else is not ours.
        const std::string rest = name.substr(prefix.size());
        const std::size_t d1 = rest.find('-');
        const std::size_t d2 = d1 == std::string::npos ? d1 : rest.find('-', d1 + 1);
        if (d2 == std::string::npos || !allDigits(rest.substr(0, d1)) || !allDigits(rest.substr(d1 + 1, d2 - d1 - 1)) ||
            !allDigits(rest.substr(d2 + 1)) || d1 > 18)
            continue;
        const unsigned long long pid = std::stoull(rest.substr(0, d1));
        if (pid == 0 || pid > static_cast<unsigned long long>(std::numeric_limits<pid_t>::max())) continue;
        if (kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to judge)
        std::error_code removeError, statusError;
        if (fs::is_regular_file(it->symlink_status(statusError)) && !statusError) fs::remove(it->path(), removeError);
    }
#else
    (void)path;
#endif
}

bool replaceFile(const std::string& from, const std::string& to) {
#ifdef _WIN32
    return MoveFileExA(from.c_str(), to.c_str(), MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH) != 0;
#else
    return std::rename(from.c_str(), to.c_str()) == 0;
#endif
}

void writeFileAtomically(const std::string& path, const std::vector<std::pair<const void*, std::size_t>>& pieces) {
    removeStaleTemporaries(path);
    std::string temporary;
    std::unique_ptr<std::FILE, FileCloser> file;
    for (int attempt = 0; attempt < 16 && !file; ++attempt) {
        temporary = uniqueTemporaryPath(path);
        file.reset(std::fopen(temporary.c_str(), "wbx"));
        if (!file && errno != EEXIST) break;
    }
    if (!file)
        throw AtomicFileError("cannot save '" + path + "': cannot create the temporary file '" + temporary +
                              "': " + std::strerror(errno) + "; check that the folder exists and is writable");
    const auto abandon = [&](const std::string& why) {
        const int err = errno;
        file.reset();
        std::remove(temporary.c_str());
        throw AtomicFileError("cannot save '" + path + "': " + why + ": " + std::strerror(err) +
                              " (the disk may be full); nothing was written");
    };
    for (const auto& piece : pieces)
        if (piece.second && std::fwrite(piece.first, 1, piece.second, file.get()) != piece.second) abandon("write error");
    if (std::fflush(file.get()) != 0) abandon("write error");
#ifdef _WIN32
    if (_commit(_fileno(file.get())) != 0) abandon("cannot flush the file to disk");
#else
    if (fsync(fileno(file.get())) != 0) abandon("cannot flush the file to disk");
#endif
    if (std::fclose(file.release()) != 0) {
        const int err = errno;
        std::remove(temporary.c_str());
        throw AtomicFileError("cannot save '" + path + "': write error: " + std::strerror(err) + "; nothing was written");
    }
    if (!replaceFile(temporary, path)) {
        const int err = errno;
        std::remove(temporary.c_str());
        throw AtomicFileError("cannot save '" + path + "': cannot replace the file: " + std::string(std::strerror(err)));
    }
}

std::string outputPathProblem(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (path.empty()) return "No output file name was given: choose a file in a folder you can write to.";
    const fs::path target(path);
    if (fs::is_directory(target, ec))
        return "'" + path + "' is a folder, not a file name: give a file name inside it (e.g. " +
               (target / "result").string() + ").";
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    if (!fs::exists(folder, ec))
        return "The folder '" + folder.string() + "' does not exist: create it or choose a file in another folder.";
    if (!fs::is_directory(folder, ec))
        return "'" + folder.string() + "' is a file, not a folder: choose a file in a folder.";
#ifndef _WIN32
    if (access(folder.c_str(), W_OK | X_OK) != 0)
        return "The folder '" + folder.string() + "' is not writable (" + std::strerror(errno) +
               "): choose another folder or change its permissions.";
#endif
    return {};
}

AtomicFileSet::~AtomicFileSet() {
    if (committed_) return;
    for (const std::string& path : temporaries_) std::remove(path.c_str());
}

std::string AtomicFileSet::add(const std::string& finalPath) {
    removeStaleTemporaries(finalPath);
    finals_.push_back(finalPath);
    temporaries_.push_back(uniqueTemporaryPath(finalPath));
    return temporaries_.back();
}

void AtomicFileSet::commit() {
    namespace fs = std::filesystem;
    // 1. Keep the old contents of the destinations that exist, under their own unique names.
    std::vector<std::string> backups(finals_.size());
    const auto dropBackups = [&] {
        for (const std::string& b : backups)
            if (!b.empty()) std::remove(b.c_str());
    };
    for (std::size_t i = 0; i < finals_.size(); ++i) {
        std::error_code ec;
        if (!fs::exists(fs::symlink_status(finals_[i], ec))) continue;
        if (fs::is_directory(finals_[i], ec)) {
            dropBackups();
            throw AtomicFileError("cannot save '" + finals_[i] + "': a folder of that name is in the way; remove it "
                                  "or choose another name (nothing was written)");
        }
        backups[i] = uniqueTemporaryPath(finals_[i]);
        fs::create_hard_link(finals_[i], backups[i], ec);
        if (ec) {
            std::error_code copyError;
            fs::copy_file(finals_[i], backups[i], fs::copy_options::overwrite_existing, copyError);
            if (copyError) {
                backups[i].clear();
                dropBackups();
                throw AtomicFileError("cannot save '" + finals_[i] + "': cannot keep its old contents while the new "
                                      "files are put in place: " + copyError.message() +
                                      "; check the folder's permissions and free space (nothing was written)");
            }
        }
    }
    // 2. Every temporary over its destination; on a failure, undo the renames already made.
    for (std::size_t i = 0; i < finals_.size(); ++i) {
        if (replaceFile(temporaries_[i], finals_[i])) continue;
        const int err = errno;
        for (std::size_t j = 0; j < i; ++j) {
            if (!backups[j].empty()) {
                replaceFile(backups[j], finals_[j]);
                backups[j].clear();
            } else {
                std::remove(finals_[j].c_str());
            }
        }
        dropBackups();
        throw AtomicFileError("cannot save '" + finals_[i] + "': cannot replace the file: " + std::strerror(err) +
                              "; check that the name is not a folder and the folder is writable (no file was "
                              "changed)");
    }
    committed_ = true;
    dropBackups();
}

}  // namespace rad
