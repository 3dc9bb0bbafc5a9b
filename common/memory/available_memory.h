// How much memory a long computation may still take: the kernel's MemAvailable (what can be
// allocated without swapping, page cache included), so that a job too large for the machine is
// refused up front with the figures instead of failing, or thrashing, hours in.
#pragma once

#include <cstddef>
#include <string>

namespace rad {

// Bytes available now (Linux /proc/meminfo MemAvailable; else free physical pages); 0 if unknown.
std::size_t availableMemoryBytes();

// "1.4 GB", "350 MB": a byte count for a message.
std::string describeBytes(double bytes);

}  // namespace rad
