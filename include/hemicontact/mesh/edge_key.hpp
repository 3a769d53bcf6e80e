#pragma once
/// @file edge_key.hpp  One 64-bit key per undirected edge (a, b), and a flat hash map from such keys
/// to ints: the bisections' edge numbers and midpoints; one key per triangular face.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace hemicontact {

/// @return the same key for (a, b) and (b, a).
inline std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

/// @return the same key for every order of a face's three nodes (them, sorted).
inline std::array<int, 3> face_key(int a, int b, int c) {
  std::array<int, 3> k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

/// Open addressing with linear probing over a power-of-two table kept at most half full, keys mixed
/// by splitmix64's finalizer. No erase. Against std::unordered_map: no allocation per entry and one
/// cache line per probe (the 2D bisection spent more time in unordered_map's node allocations than
/// in the bisection itself).
class EdgeMap {
 public:
  /// @param expected how many keys will be inserted (the table is sized for it; it grows if exceeded)
  explicit EdgeMap(size_t expected = 16) { rehash(expected); }
  /// @return the value stored for @p key, or −1 if none.
  int find(std::uint64_t key) const {
    for (size_t i = slot(key);; i = (i + 1) & m_mask) {
      if (m_keys[i] == EMPTY) return -1;
      if (m_keys[i] == key) return m_values[i];
    }
  }
  /// Insert @p key → @p value unless @p key is present. @return (the stored value, whether it was inserted).
  std::pair<int, bool> emplace(std::uint64_t key, int value) {
    if (2 * (m_size + 1) > m_keys.size()) rehash(2 * m_size + 2);
    for (size_t i = slot(key);; i = (i + 1) & m_mask) {
      if (m_keys[i] == key) return {m_values[i], false};
      if (m_keys[i] == EMPTY) {
        m_keys[i] = key;
        m_values[i] = value;
        ++m_size;
        return {value, true};
      }
    }
  }
  /// @return the number of keys stored.
  size_t size() const { return m_size; }

 private:
  static constexpr std::uint64_t EMPTY = ~std::uint64_t{0};  // no edge (a ≤ b < 2^32 − 1) has it
  size_t slot(std::uint64_t x) const {
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return static_cast<size_t>(x ^ (x >> 31)) & m_mask;
  }
  void rehash(size_t expected) {
    size_t cap = 16;
    while (cap < 2 * expected) cap *= 2;
    std::vector<std::uint64_t> keys(cap, EMPTY);
    std::vector<int> values(cap, -1);
    keys.swap(m_keys);
    values.swap(m_values);
    m_mask = cap - 1;
    m_size = 0;
    for (size_t i = 0; i < keys.size(); ++i)
      if (keys[i] != EMPTY) emplace(keys[i], values[i]);
  }
  std::vector<std::uint64_t> m_keys;
  std::vector<int> m_values;
  size_t m_mask = 0, m_size = 0;
};

}  // namespace hemicontact
