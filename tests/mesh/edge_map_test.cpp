// EdgeMap (mesh/edge_key.hpp): the bisections' flat edge → int table agrees with std::map on a
// random workload that makes it grow from the smallest table, keeps the first value of a key, and
// answers −1 for keys never inserted.
#include <hemicontact/mesh/edge_key.hpp>

#include <gtest/gtest.h>

#include <map>
#include <random>

using namespace hemicontact;

TEST(EdgeMap, AgreesWithAnOrderedMapWhileGrowing) {
  EdgeMap table(1);
  std::map<std::uint64_t, int> truth;
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> node(0, 3000);
  for (int k = 0; k < 50000; ++k) {
    const std::uint64_t key = edge_key(node(rng), node(rng));
    const auto [value, fresh] = table.emplace(key, k);
    const auto [it, fresh_truth] = truth.emplace(key, k);
    ASSERT_EQ(fresh, fresh_truth);
    ASSERT_EQ(value, it->second);
  }
  EXPECT_EQ(table.size(), truth.size());
  for (const auto& [key, value] : truth) ASSERT_EQ(table.find(key), value);
  EXPECT_EQ(table.find(edge_key(3001, 3002)), -1);
  EXPECT_EQ(edge_key(7, 3), edge_key(3, 7));
}
