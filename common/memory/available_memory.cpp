#include "memory/available_memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace rad {

namespace {

// The value after `key` in a "Key:   value kB" file (/proc/meminfo, /proc/self/status), in bytes.
bool readKilobytesLine(const char* path, const std::string& key, std::size_t& bytes) {
    std::ifstream file(path);
    std::string line;
    while (std::getline(file, line)) {  // line by line: /proc/self/status has lines without numbers
        if (line.compare(0, key.size(), key) != 0) continue;
        std::istringstream value(line.substr(key.size()));
        std::size_t kilobytes = 0;
        if (!(value >> kilobytes)) return false;
        bytes = kilobytes * 1024;
        return true;
    }
    return false;
}

// A cgroup file holding one number, or "max" (v2); false when absent or unlimited.
bool readCgroupNumber(const std::string& path, std::size_t& value) {
    std::ifstream file(path);
    std::string text;
    if (!(file >> text) || text == "max") return false;
    try {
        value = static_cast<std::size_t>(std::stoull(text));
        return value < (std::size_t(1) << 60);  // cgroup v1 writes "unlimited" as about 2^63
    } catch (const std::exception&) {
        return false;
    }
}

// Headroom 0 means "no limit" in this file's functions; a limit already reached leaves 1 byte.
std::size_t headroom(std::size_t limit, std::size_t used) { return limit > used ? limit - used : 1; }

// The tighter of two headrooms, 0 standing for "no limit".
std::size_t tighter(std::size_t a, std::size_t b) { return a == 0 ? b : b == 0 ? a : std::min(a, b); }

// The tightest cgroup limit on `group` and its ancestors under `mount` (a limit on an ancestor binds
// too). Inside a container the group's path may not exist in the container's view of the mount:
// its ancestors, down to the mount's root (the container's own group), are still read.
std::size_t limitHeadroomUpTo(const std::string& mount, std::string group, const char* limitFile,
                              const char* usageFile) {
    std::size_t tightest = 0;
    for (;;) {
        const std::string folder = mount + (group == "/" ? std::string() : group);
        std::size_t limit = 0, used = 0;
        if (readCgroupNumber(folder + "/" + limitFile, limit) && readCgroupNumber(folder + "/" + usageFile, used))
            tightest = tighter(tightest, headroom(limit, used));
        if (group.empty() || group == "/") return tightest;
        group = group.substr(0, group.find_last_of('/'));
    }
}

}  // namespace

std::size_t machineAvailableMemoryBytes() {
    std::size_t bytes = 0;
    if (readKilobytesLine("/proc/meminfo", "MemAvailable:", bytes)) return bytes;
    const long pages = sysconf(_SC_AVPHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
    return pages > 0 && pageSize > 0 ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(pageSize) : 0;
}

std::size_t addressSpaceHeadroomBytes() {
    rlimit limit{};
    if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return 0;
    std::size_t used = 0;
    if (!readKilobytesLine("/proc/self/status", "VmSize:", used)) return 0;
    return headroom(static_cast<std::size_t>(limit.rlim_cur), used);
}

std::size_t cgroupHeadroomBytes() {
    // The process's group in each hierarchy: "0::/path" (v2), "N:memory:/path" (v1 memory controller).
    std::ifstream membership("/proc/self/cgroup");
    std::string line, unified, memory;
    while (std::getline(membership, line)) {
        if (line.rfind("0::", 0) == 0) unified = line.substr(3);
        const std::size_t colon = line.find(":memory:");
        if (colon != std::string::npos) memory = line.substr(colon + 8);
    }
    std::size_t tightest = 0;
    if (!unified.empty())
        tightest = tighter(tightest, limitHeadroomUpTo("/sys/fs/cgroup", unified, "memory.max", "memory.current"));
    if (!memory.empty())
        tightest = tighter(tightest, limitHeadroomUpTo("/sys/fs/cgroup/memory", memory, "memory.limit_in_bytes",
                                                       "memory.usage_in_bytes"));
    return tightest;
}

std::size_t availableMemoryBytes() {
    return tighter(machineAvailableMemoryBytes(), tighter(addressSpaceHeadroomBytes(), cgroupHeadroomBytes()));
}

std::string describeBytes(double bytes) {
    char text[32];
    if (bytes >= 1e9) std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
    else std::snprintf(text, sizeof text, "%.0f MB", bytes / 1e6);
    return text;
}

}  // namespace rad
