// Recycled memory for packet payloads.
//
// Every Packet payload lives in a small block from this pool, so a pipeline in steady state
// allocates nothing from the system heap per packet: blocks freed by a consumer thread go
// back to a per-thread cache and, in batches, to a shared list the producer refills from.
// Blocks larger than the biggest size class come from operator new.
//
// Thread-safe. Under AddressSanitizer the pool is bypassed so use-after-free stays visible.
#pragma once

#include <cstddef>

namespace marvin::graph::detail {

// Returns a block of at least `size` bytes aligned for any scalar type. Never returns null
// (throws std::bad_alloc like operator new).
void* pool_allocate(std::size_t size);

// Gives back a block from pool_allocate(); `size` must be the size that was requested.
void pool_free(void* block, std::size_t size) noexcept;

}  // namespace marvin::graph::detail
