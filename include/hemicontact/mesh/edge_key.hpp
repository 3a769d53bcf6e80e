#pragma once
/// @file edge_key.hpp  One 64-bit key per undirected edge (a, b), for hash maps of edges: the
/// bisection's midpoints and the estimator's traction jumps.

#include <cstdint>
#include <utility>

namespace hemicontact {

/// @return the same key for (a, b) and (b, a).
inline std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

}  // namespace hemicontact
