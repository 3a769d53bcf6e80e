#include <hemicontact/problem/solution.hpp>

namespace hemicontact {

std::map<std::string, int> Solution::status_counts() const {
  std::map<std::string, int> c{{"separated", 0}, {"compliance", 0}, {"contact", 0},
                               {"stick", 0},     {"slip+", 0},      {"slip-", 0}};
  for (const auto& s : status) {
    ++c[to_string(s.normal)];
    ++c[to_string(s.tangential)];
  }
  return c;
}

}  // namespace hemicontact
