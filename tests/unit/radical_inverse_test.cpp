// radicalInverse2: the base-2 digits of i mirrored about the binary point, checked on values
// written out by hand, and the property the Hammersley sets rely on: the first 2^m values are the
// multiples of 2^-m, each once.
#include "sampling/radical_inverse.h"

#include <gtest/gtest.h>

#include <set>

TEST(RadicalInverse, MirrorsTheBinaryDigits) {
    EXPECT_EQ(rad::radicalInverse2(0), 0.0);
    EXPECT_EQ(rad::radicalInverse2(1), 0.5);     // 0.1b
    EXPECT_EQ(rad::radicalInverse2(2), 0.25);    // 0.01b
    EXPECT_EQ(rad::radicalInverse2(3), 0.75);    // 0.11b
    EXPECT_EQ(rad::radicalInverse2(6), 0.375);   // 110b -> 0.011b
    EXPECT_EQ(rad::radicalInverse2(11), 0.8125); // 1011b -> 0.1101b
    EXPECT_EQ(rad::radicalInverse2(0x80000000u), 1.0 / 4294967296.0);
}

TEST(RadicalInverse, TheFirstPowerOfTwoValuesAreTheMultiplesOfItsInverse) {
    for (const int m : {1, 4, 10}) {
        const std::uint32_t count = 1u << m;
        std::set<std::uint32_t> steps;
        for (std::uint32_t i = 0; i < count; ++i) {
            const double scaled = rad::radicalInverse2(i) * count;
            ASSERT_EQ(scaled, double(std::uint32_t(scaled))) << i;
            steps.insert(std::uint32_t(scaled));
        }
        EXPECT_EQ(steps.size(), count);
        EXPECT_EQ(*steps.rbegin(), count - 1);
    }
}
