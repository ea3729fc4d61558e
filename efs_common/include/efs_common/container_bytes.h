// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// What a map's memoryBytes() counts for a node-based hash container, in one place: the bucket
// array, and per element a node holding the next pointer, the value and the cached hash
// (libstdc++'s layout). Heap memory the values themselves own is the caller's to add.
#pragma once

#include <cstddef>

namespace efs {

template <typename HashContainer>
std::size_t hashContainerBytes(const HashContainer& c) {
  constexpr std::size_t node =
      sizeof(void*) + sizeof(typename HashContainer::value_type) + sizeof(std::size_t);
  return c.size() * node + c.bucket_count() * sizeof(void*);
}

}  // namespace efs
