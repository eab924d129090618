#include "graph/packet_pool.h"

#include <array>
#include <mutex>
#include <new>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define MARVIN_GRAPH_POOL_BYPASS 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MARVIN_GRAPH_POOL_BYPASS 1
#endif
#endif

namespace marvin::graph::detail {
#ifndef MARVIN_GRAPH_POOL_BYPASS
namespace {

constexpr std::size_t kClassCount = 4;
constexpr std::array<std::size_t, kClassCount> kClassSize = {32, 64, 128, 256};
// A thread keeps up to kCacheMax blocks per class and moves kTransferBatch at a time to or from the
// shared list, so the shared mutex is taken once per kTransferBatch packets at most.
constexpr std::size_t kCacheMax = 256;
constexpr std::size_t kTransferBatch = 64;

int class_of(std::size_t size) {
  for (std::size_t i = 0; i < kClassCount; ++i) {
    if (size <= kClassSize[i]) return static_cast<int>(i);
  }
  return -1;
}

struct SharedLists {
  std::mutex mutex;
  std::array<std::vector<void*>, kClassCount> free;
};

// Deliberately never destroyed: thread caches may hand blocks back during static
// destruction, and the blocks stay reachable from here (no leak report).
SharedLists& shared() {
  static SharedLists* lists = new SharedLists;
  return *lists;
}

// Trivially destructible, so still readable while (and after) the thread's cache is destroyed.
thread_local bool t_cache_gone = false;

struct ThreadCache {
  std::array<std::array<void*, kCacheMax>, kClassCount> blocks{};
  std::array<std::size_t, kClassCount> count{};

  ~ThreadCache() {
    t_cache_gone = true;
    SharedLists& s = shared();
    std::lock_guard lock(s.mutex);
    for (std::size_t c = 0; c < kClassCount; ++c) {
      for (std::size_t i = 0; i < count[c]; ++i) s.free[c].push_back(blocks[c][i]);
    }
  }
};

ThreadCache& cache() {
  thread_local ThreadCache tc;
  return tc;
}

}  // namespace
#endif

void* pool_allocate(std::size_t size) {
#ifdef MARVIN_GRAPH_POOL_BYPASS
  return ::operator new(size);
#else
  const int c = class_of(size);
  if (c < 0) return ::operator new(size);
  const auto cls = static_cast<std::size_t>(c);
  if (t_cache_gone) return ::operator new(kClassSize[cls]);
  ThreadCache& tc = cache();
  if (tc.count[cls] == 0) {
    SharedLists& s = shared();
    {
      std::lock_guard lock(s.mutex);
      std::vector<void*>& list = s.free[cls];
      while (tc.count[cls] < kTransferBatch && !list.empty()) {
        tc.blocks[cls][tc.count[cls]++] = list.back();
        list.pop_back();
      }
    }
    if (tc.count[cls] == 0) return ::operator new(kClassSize[cls]);
  }
  return tc.blocks[cls][--tc.count[cls]];
#endif
}

void pool_free(void* block, std::size_t size) noexcept {
#ifdef MARVIN_GRAPH_POOL_BYPASS
  ::operator delete(block);
  (void)size;
#else
  const int c = class_of(size);
  if (c < 0) {
    ::operator delete(block);
    return;
  }
  const auto cls = static_cast<std::size_t>(c);
  if (t_cache_gone) {  // packets released by static destructors after thread exit began
    ::operator delete(block);
    return;
  }
  ThreadCache& tc = cache();
  if (tc.count[cls] == kCacheMax) {
    SharedLists& s = shared();
    try {
      std::lock_guard lock(s.mutex);
      for (std::size_t i = 0; i < kTransferBatch; ++i) s.free[cls].push_back(tc.blocks[cls][--tc.count[cls]]);
    } catch (...) {
      // Out of memory growing the shared list: the block just goes back to the heap.
      ::operator delete(block);
      return;
    }
  }
  tc.blocks[cls][tc.count[cls]++] = block;
#endif
}

}  // namespace marvin::graph::detail
