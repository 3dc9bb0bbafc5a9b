// A min-priority queue of payloads by cost, for the edge-collapse engine: a 4-ary heap of 16-byte
// (cost, slot) keys over a pool of payloads that reuses freed slots. The collapse loop pushes and
// pops millions of entries (most of them stale) and was bound by the cache misses of sifting 48-byte
// entries through a binary heap; here a node's four children share one or two cache lines and the
// heap is a third of the size. Equal costs come out by the caller's tie key, then by slot, which
// depends only on the order of the pushes and pops: a run is deterministic.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace rad {

template <class Payload>
class CostQueue {
public:
    void reserve(std::size_t n) {
        heap_.reserve(n);
        pool_.reserve(n);
    }
    void clear() {
        heap_.clear();
        pool_.clear();
        free_.clear();
    }
    bool empty() const { return heap_.empty(); }
    std::size_t size() const { return heap_.size(); }

    void push(double cost, std::uint32_t tie, const Payload& payload) {
        std::uint32_t slot;
        if (!free_.empty()) {
            slot = free_.back();
            free_.pop_back();
            pool_[slot] = payload;
        } else {
            slot = static_cast<std::uint32_t>(pool_.size());
            pool_.push_back(payload);
        }
        heap_.push_back({cost, tie, slot});
        siftUp(heap_.size() - 1);
    }

    // Removes the cheapest entry (the queue must not be empty) and returns its cost and payload.
    std::pair<double, Payload> pop() {
        const Key top = heap_.front();
        const Key last = heap_.back();
        heap_.pop_back();
        if (!heap_.empty()) siftDown(last);
        free_.push_back(top.slot);
        return {top.cost, pool_[top.slot]};
    }

private:
    struct Key {
        double cost;
        std::uint32_t tie, slot;
    };
    static bool before(const Key& x, const Key& y) {
        if (x.cost != y.cost) return x.cost < y.cost;
        if (x.tie != y.tie) return x.tie < y.tie;
        return x.slot < y.slot;
    }

    void siftUp(std::size_t i) {
        const Key moving = heap_[i];
        while (i > 0) {
            const std::size_t parent = (i - 1) / 4;
            if (!before(moving, heap_[parent])) break;
            heap_[i] = heap_[parent];
            i = parent;
        }
        heap_[i] = moving;
    }

    // Places `moving` from the root down (the root's slot is free).
    void siftDown(const Key& moving) {
        const std::size_t n = heap_.size();
        std::size_t i = 0;
        for (;;) {
            const std::size_t first = 4 * i + 1;
            if (first >= n) break;
            const std::size_t last = first + 4 < n ? first + 4 : n;
            std::size_t best = first;
            for (std::size_t c = first + 1; c < last; ++c)
                if (before(heap_[c], heap_[best])) best = c;
            if (!before(heap_[best], moving)) break;
            heap_[i] = heap_[best];
            i = best;
        }
        heap_[i] = moving;
    }

    std::vector<Key> heap_;
    std::vector<Payload> pool_;
    std::vector<std::uint32_t> free_;
};

}  // namespace rad
