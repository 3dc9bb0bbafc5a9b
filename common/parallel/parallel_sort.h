// Sorting on all the cores: libstdc++'s parallel mode (a multiway mergesort over OpenMP threads), for
// the arrays of millions of keys the simplification sorts (faces and edges when checking its input,
// the ranked collapses of each pass). Short ranges, or one thread, take std::sort. Not stable: every
// caller sorts by a total order, or keys whose equal values cannot be told apart, so the result is
// the same on any thread count.
#pragma once

#include <omp.h>

#include <algorithm>
#include <parallel/algorithm>

namespace rad {

template <class RandomIt, class Less>
void sortInParallel(RandomIt begin, RandomIt end, Less less, int threads = 0) {
    constexpr long kParallelFrom = 65536;  // below, starting the threads costs more than it saves
    const int team = threads > 0 ? threads : omp_get_max_threads();
    if (team < 2 || end - begin < kParallelFrom) {
        std::sort(begin, end, less);
        return;
    }
    __gnu_parallel::sort(begin, end, less, __gnu_parallel::multiway_mergesort_tag(team));
}

}  // namespace rad
