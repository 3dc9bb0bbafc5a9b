// availableMemoryBytes and describeBytes (memory/available_memory.h).
#include "memory/available_memory.h"

#include <gtest/gtest.h>

#include <unistd.h>

namespace {

TEST(AvailableMemory, IsPositiveAndBelowThePhysicalMemory) {
    const std::size_t available = rad::availableMemoryBytes();
    const std::size_t physical = std::size_t(sysconf(_SC_PHYS_PAGES)) * std::size_t(sysconf(_SC_PAGESIZE));
    EXPECT_GT(available, 16u << 20);  // any machine running the tests has more than 16 MB free
    EXPECT_LE(available, physical);
}

TEST(AvailableMemory, DescribesBytesInMegabytesOrGigabytes) {
    EXPECT_EQ(rad::describeBytes(350e6), "350 MB");
    EXPECT_EQ(rad::describeBytes(1.44e9), "1.4 GB");
    EXPECT_EQ(rad::describeBytes(18.7e9), "18.7 GB");
}

}  // namespace
