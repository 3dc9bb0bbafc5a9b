// The readers under fuzz take a path: each harness writes libFuzzer's input to a file in a private
// folder (the folder named by an environment variable, else one per process under /dev/shm or /tmp)
// and hands the path to the reader.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <unistd.h>

namespace fuzz {

// The harness's working folder: $variable when set (the scripts put fixed companions there, e.g. the
// base mesh an .rpm names), else a private folder made once for this process. One variable per
// harness: the folder is fixed at the first call.
inline const std::string& workFolder(const char* variable) {
    static const std::string dir = [variable] {
        if (const char* given = std::getenv(variable)) return std::string(given);
        const char* base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
        std::string made = std::string(base) + "/radiance_fuzz_" + std::to_string(getpid());
        if (std::system(("mkdir -p '" + made + "'").c_str()) != 0) std::abort();
        return made;
    }();
    return dir;
}

// Writes the input to <folder>/<name> and returns that path; a failed write aborts the run (it is the
// harness's fault, not the reader's).
inline std::string writeInput(const char* variable, const std::string& name, const std::uint8_t* data,
                              std::size_t size) {
    const std::string path = workFolder(variable) + "/" + name;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) std::abort();
    const bool written = std::fwrite(data, 1, size, f) == size;
    if (std::fclose(f) != 0 || !written) std::abort();
    return path;
}

}  // namespace fuzz
