// The edge-collapse engine's priority queue (simplify/cost_queue.h): entries come out cheapest
// first whatever the interleaving of pushes and pops, ties by slot, payloads intact.
#include "simplify/cost_queue.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace {

struct Payload {
    std::uint32_t id;
    double check;  // a value derived from the id: a payload mixed up with another's shows
};

}  // namespace

TEST(CostQueue, PopsInCostOrderUnderInterleavedPushesAndPops) {
    std::mt19937 rng(17);
    std::uniform_int_distribution<int> coarse(0, 50);  // few distinct costs: many ties
    rad::CostQueue<Payload> queue;
    // A reference: every live (cost, id), the cheapest taken by a linear scan.
    std::vector<std::pair<double, std::uint32_t>> live;
    std::uint32_t nextId = 0;
    double lastPopped = -1.0;
    int pops = 0;
    for (int step = 0; step < 20000; ++step) {
        const bool pushing = live.empty() || rng() % 3 != 0;
        if (pushing) {
            // Costs never below the last popped one, as in the collapse loop's usual case, and
            // sometimes far below, as when a re-priced edge got cheaper.
            const double cost = (rng() % 10 == 0) ? coarse(rng) * 0.01 : lastPopped + 1.0 + coarse(rng);
            queue.push(cost, nextId % 7, {nextId, cost * 3.0 + nextId});
            live.push_back({cost, nextId});
            ++nextId;
        } else {
            const auto [cost, payload] = queue.pop();
            ++pops;
            const auto cheapest = std::min_element(live.begin(), live.end(), [](const auto& x, const auto& y) {
                return x.first < y.first;
            });
            ASSERT_EQ(cost, cheapest->first) << "pop " << pops;
            // The payload is one of the live entries of that cost, with its own check value.
            const auto found = std::find(live.begin(), live.end(), std::make_pair(cost, payload.id));
            ASSERT_NE(found, live.end()) << "pop " << pops;
            EXPECT_EQ(payload.check, cost * 3.0 + payload.id);
            live.erase(found);
            lastPopped = cost;
        }
        ASSERT_EQ(queue.size(), live.size());
    }
    while (!queue.empty()) {
        const double cost = queue.pop().first;
        const auto cheapest = std::min_element(live.begin(), live.end());
        ASSERT_EQ(cost, cheapest->first);
        live.erase(std::find_if(live.begin(), live.end(), [&](const auto& e) { return e.first == cost; }));
    }
    EXPECT_TRUE(live.empty());
    EXPECT_GT(pops, 5000);
}

TEST(CostQueue, EqualCostsComeOutInTheSameOrderOnEveryRun) {
    auto run = [] {
        rad::CostQueue<Payload> queue;
        std::vector<std::uint32_t> order;
        for (std::uint32_t i = 0; i < 100; ++i) queue.push(i % 2 == 0 ? 1.0 : 2.0, i % 3, {i, 0.0});
        for (int i = 0; i < 30; ++i) order.push_back(queue.pop().second.id);  // frees slots, reused below
        for (std::uint32_t i = 100; i < 150; ++i) queue.push(1.0, i % 3, {i, 0.0});
        while (!queue.empty()) order.push_back(queue.pop().second.id);
        return order;
    };
    const std::vector<std::uint32_t> first = run();
    EXPECT_EQ(first.size(), 150u);
    EXPECT_EQ(run(), first);
    // Cost 1 before cost 2: the 50 even ids pushed first and the 50 pushed later, then the odd ones;
    // the first 30, all of cost 1, by tie key: 0 (ids 0, 6, ..., 96: 17 of them), then 1.
    for (std::size_t k = 0; k < 30; ++k) EXPECT_EQ(first[k] % 2, 0u) << k;
    for (std::size_t k = 0; k < 17; ++k) EXPECT_EQ(first[k] % 3, 0u) << k;
    for (std::size_t k = 17; k < 30; ++k) EXPECT_EQ(first[k] % 3, 1u) << k;
    for (std::size_t k = 100; k < 150; ++k) EXPECT_EQ(first[k] % 2, 1u) << k;
}
