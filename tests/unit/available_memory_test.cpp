// availableMemoryBytes and describeBytes (memory/available_memory.h).
#include "memory/available_memory.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace {

TEST(AvailableMemory, IsPositiveAndBelowThePhysicalMemory) {
    const std::size_t available = rad::availableMemoryBytes();
    const std::size_t physical = std::size_t(sysconf(_SC_PHYS_PAGES)) * std::size_t(sysconf(_SC_PAGESIZE));
    EXPECT_GT(available, 16u << 20);  // any machine running the tests has more than 16 MB free
    EXPECT_LE(available, physical);
}

std::size_t virtualMemoryBytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmSize:", 0) == 0) return std::stoull(line.substr(7)) * 1024;  // "VmSize:  123 kB"
    return 0;
}

// Run in a child process (the limit must not bind the other tests): sets RLIMIT_AS to what the
// process uses plus 300 MiB and exits with 0 when the headroom reported matches, 1 when not.
[[noreturn]] void checkHeadroomUnderAnAddressSpaceLimit() {
    const std::size_t headroom = std::size_t(300) << 20;
    const std::size_t used = virtualMemoryBytes();
    rlimit limit{};
    getrlimit(RLIMIT_AS, &limit);
    limit.rlim_cur = used + headroom;
    if (used == 0 || setrlimit(RLIMIT_AS, &limit) != 0) {
        std::fprintf(stderr, "cannot set the limit\n");
        std::_Exit(2);
    }
    const std::size_t left = rad::addressSpaceHeadroomBytes(), available = rad::availableMemoryBytes();
    // The process may have mapped a little more since VmSize was read: within 32 MiB.
    const bool ok = left <= headroom && left + (std::size_t(32) << 20) >= headroom && available <= left;
    std::fprintf(stderr, "headroom %zu, available %zu\n", left, available);
    std::_Exit(ok ? 0 : 1);
}

// Under `ulimit -v` (RLIMIT_AS, as batch schedulers set it) a large allocation fails long before the
// machine's MemAvailable is reached: the headroom the limit leaves is what a job may take.
TEST(AvailableMemory, AnAddressSpaceLimitBoundsWhatIsAvailable) {
    EXPECT_EXIT(checkHeadroomUnderAnAddressSpaceLimit(), ::testing::ExitedWithCode(0), "headroom");
}

TEST(AvailableMemory, WithoutAnAddressSpaceLimitThereIsNoHeadroomBound) {
    rlimit limit{};
    ASSERT_EQ(getrlimit(RLIMIT_AS, &limit), 0);
    if (limit.rlim_cur == RLIM_INFINITY) EXPECT_EQ(rad::addressSpaceHeadroomBytes(), 0u);
    else EXPECT_GT(rad::addressSpaceHeadroomBytes(), 0u);
}

TEST(AvailableMemory, DescribesBytesInMegabytesOrGigabytes) {
    EXPECT_EQ(rad::describeBytes(350e6), "350 MB");
    EXPECT_EQ(rad::describeBytes(1.44e9), "1.4 GB");
    EXPECT_EQ(rad::describeBytes(18.7e9), "18.7 GB");
}

}  // namespace
