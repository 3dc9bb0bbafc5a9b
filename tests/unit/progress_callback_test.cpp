// The cores' progress and cancellation contract (progress/progress_callback.h).
#include "progress/progress_callback.h"

#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

TEST(ProgressCallback, ReportProgressPassesThroughAndThrowsOnStop) {
    EXPECT_NO_THROW(rad::reportProgress({}, 0.5, "stage"));  // no callback: nothing to ask
    std::vector<std::pair<double, std::string>> seen;
    const rad::ProgressCallback keepGoing = [&](double f, const char* stage) {
        seen.emplace_back(f, stage);
        return true;
    };
    rad::reportProgress(keepGoing, 0.25, "first");
    rad::reportProgress(keepGoing, 0.5, nullptr);  // a null stage reaches the callback as ""
    ASSERT_EQ(seen.size(), 2u);
    EXPECT_EQ(seen[0].first, 0.25);
    EXPECT_EQ(seen[0].second, "first");
    EXPECT_EQ(seen[1].second, "");
    const rad::ProgressCallback stop = [](double, const char*) { return false; };
    EXPECT_THROW(rad::reportProgress(stop, 0.1, "x"), rad::OperationCancelled);
}

TEST(ProgressCallback, RangeMapsAndClampsFractions) {
    EXPECT_FALSE(rad::progressRange({}, 0.2, 0.4));  // empty stays empty
    std::vector<double> seen;
    const rad::ProgressCallback outer = [&](double f, const char*) {
        seen.push_back(f);
        return f < 0.35;
    };
    const rad::ProgressCallback step = rad::progressRange(outer, 0.2, 0.4);
    EXPECT_TRUE(step(0.0, "s"));
    EXPECT_TRUE(step(0.5, "s"));
    EXPECT_TRUE(step(-3.0, "s"));  // clamped to the start
    EXPECT_TRUE(step(std::numeric_limits<double>::quiet_NaN(), "s"));
    EXPECT_FALSE(step(2.0, "s"));  // clamped to the end, where the outer callback asks to stop
    ASSERT_EQ(seen.size(), 5u);
    EXPECT_DOUBLE_EQ(seen[0], 0.2);
    EXPECT_DOUBLE_EQ(seen[1], 0.3);
    EXPECT_DOUBLE_EQ(seen[2], 0.2);
    EXPECT_DOUBLE_EQ(seen[3], 0.2);
    EXPECT_DOUBLE_EQ(seen[4], 0.4);
}

TEST(ProgressCallback, ConsecutiveRangesNeverGoBack) {
    // 0.03 + (0.33 - 0.03) * 1 is 0.33000000000000007 in doubles: unclamped, the end of the first
    // step would lie past the start of the next one.
    std::vector<double> seen;
    const rad::ProgressCallback outer = [&](double f, const char*) {
        seen.push_back(f);
        return true;
    };
    const rad::ProgressCallback first = rad::progressRange(outer, 0.03, 0.33);
    const rad::ProgressCallback second = rad::progressRange(outer, 0.33, 0.5);
    first(1.0, "a");
    second(0.0, "b");
    ASSERT_EQ(seen.size(), 2u);
    EXPECT_EQ(seen[0], 0.33);
    EXPECT_LE(seen[0], seen[1]);
}

TEST(ProgressCallback, LoopReportsFromTheCallingThreadOnlyAndEndsAtOne) {
    const int n = 20000;
    std::vector<double> seen;
    bool otherThread = false;
    const int caller = omp_get_thread_num();
    const rad::ProgressCallback record = [&](double f, const char*) {
        otherThread = otherThread || omp_get_thread_num() != 0;
        seen.push_back(f);
        return true;
    };
    rad::LoopProgress loop(record, "loop", n);
#pragma omp parallel for schedule(dynamic, 64)
    for (int i = 0; i < n; ++i) loop.itemDone(omp_get_thread_num() == 0);
    loop.finish();
    EXPECT_EQ(caller, 0);
    EXPECT_FALSE(otherThread);
    ASSERT_FALSE(seen.empty());
    EXPECT_LE(seen.size(), 102u);  // at most once per percent, plus the final 1
    for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]);
    EXPECT_EQ(seen.back(), 1.0);
}

TEST(ProgressCallback, LoopCountsChunksOfItemsAndReportsAtTheStepsAskedFor) {
    const std::size_t n = 100007, chunk = 32;  // the last chunk is partial
    std::vector<double> seen;
    const rad::ProgressCallback record = [&](double f, const char*) {
        seen.push_back(f);
        return true;
    };
    rad::LoopProgress loop(record, "loop", n, 1000);
    for (std::size_t begin = 0; begin < n; begin += chunk)  // serial: the calling thread does every chunk
        loop.runItem(true, [] {}, std::min(chunk, n - begin));
    loop.finish();
    EXPECT_GT(seen.size(), 500u);   // finer than once per percent
    EXPECT_LE(seen.size(), 1002u);  // at most once per permille, plus the final 1
    EXPECT_EQ(seen.front(), 32.0 / double(n));  // the fraction counts items, not chunks
    for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i], seen[i - 1]);
    EXPECT_EQ(seen.back(), 1.0);
}

TEST(ProgressCallback, LoopStopSkipsTheRestAndFinishThrows) {
    const int n = 100000;
    int calls = 0, processed = 0;
    const rad::ProgressCallback stopAtSecond = [&](double, const char*) { return ++calls < 2; };
    rad::LoopProgress loop(stopAtSecond, "loop", n);
    for (int i = 0; i < n; ++i) {  // serial: the calling thread does every item
        if (loop.stopRequested()) continue;
        ++processed;
        loop.itemDone(true);
    }
    EXPECT_TRUE(loop.stopRequested());
    EXPECT_EQ(calls, 2);
    EXPECT_LT(processed, n / 10);  // stopped at about 2 %
    EXPECT_THROW(loop.finish(), rad::OperationCancelled);
}

TEST(ProgressCallback, LoopCapturesTheFirstExceptionSkipsTheRestAndFinishRethrowsIt) {
    const int n = 100000;
    std::vector<double> seen;
    const rad::ProgressCallback record = [&](double f, const char*) {
        seen.push_back(f);
        return true;
    };
    rad::LoopProgress loop(record, "loop", n);
    std::vector<int> ran(n, 0);
#pragma omp parallel for schedule(dynamic, 16)
    for (int i = 0; i < n; ++i)
        loop.runItem(omp_get_thread_num() == 0, [&] {
            ran[i] = 1;
            if (i == 1000) throw std::invalid_argument("item 1000");
            if (i > 1000) throw std::out_of_range("a later item");  // not the first: dropped
        });
    EXPECT_TRUE(loop.stopRequested());
    int processed = 0;
    for (int r : ran) processed += r;
    EXPECT_LT(processed, n / 2);  // the items after the failure were skipped, not run
    EXPECT_EQ(ran[1000], 1);
    const std::size_t reportsBefore = seen.size();
    try {
        loop.finish();
        ADD_FAILURE() << "finish() did not rethrow the item's exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "item 1000");
    } catch (const std::out_of_range&) {
        // Another thread's later item may throw first in time; with one thread, item 1000 always does.
        if (omp_get_max_threads() == 1) ADD_FAILURE() << "a later exception replaced the first one";
    }
    EXPECT_EQ(seen.size(), reportsBefore);  // no final report of 1 after a failure
    for (double f : seen) EXPECT_LT(f, 1.0);
}

TEST(ProgressCallback, LoopCaptureIsRethrownOnTheCallingThreadEvenWithoutACallback) {
    rad::LoopProgress loop({}, "loop", 10);
    for (int i = 0; i < 10; ++i) {
        if (loop.stopRequested()) continue;
        try {
            if (i == 3) throw std::runtime_error("third");
            loop.itemDone(true);
        } catch (...) {
            loop.captureException(std::current_exception());
        }
    }
    loop.captureException(std::make_exception_ptr(std::logic_error("second capture")));  // dropped
    try {
        loop.finish();
        ADD_FAILURE() << "finish() did not rethrow the captured exception";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "third");
    }
}

}  // namespace
