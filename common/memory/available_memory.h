// How much memory a long computation may still take, so that a job too large for the machine is
// refused up front with the figures instead of failing, or thrashing, hours in. The smallest of
// what the kernel can give without swapping (MemAvailable, page cache included), what the process's
// address-space limit leaves (ulimit -v, as batch schedulers set it) and what its cgroup's memory
// limit leaves (containers, systemd slices): each of these is where a large allocation fails.
#pragma once

#include <cstddef>
#include <string>

namespace rad {

// Bytes available now; 0 if unknown. At least 1 when a limit is known and already reached.
std::size_t availableMemoryBytes();

// The machine's part alone: /proc/meminfo MemAvailable (else free physical pages); 0 if unknown.
std::size_t machineAvailableMemoryBytes();

// What RLIMIT_AS leaves beside the process's current address space (VmSize); 0 if unlimited.
std::size_t addressSpaceHeadroomBytes();

// What the cgroup memory limits leave (v2 memory.max minus memory.current, v1 limit_in_bytes minus
// usage_in_bytes; the tightest of the process's group and its ancestors); 0 if unlimited or unknown.
std::size_t cgroupHeadroomBytes();

// "1.4 GB", "350 MB": a byte count for a message.
std::string describeBytes(double bytes);

}  // namespace rad
