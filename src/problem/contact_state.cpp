#include <hemicontact/problem/contact_state.hpp>

namespace hemicontact {

const char* to_string(NormalStatus s) {
  switch (s) {
    case NormalStatus::SEPARATED: return "separated";
    case NormalStatus::COMPLIANCE: return "compliance";
    default: return "contact";
  }
}

const char* to_string(TangentialStatus s) {
  switch (s) {
    case TangentialStatus::STICK: return "stick";
    case TangentialStatus::SLIP_PLUS: return "slip+";
    case TangentialStatus::SLIP_MINUS: return "slip-";
    default: return "slip";
  }
}

std::string NodeStatus::str() const { return std::string(to_string(normal)) + "/" + to_string(tangential); }

const std::array<const char*, 7>& status_count_names() {
  static const std::array<const char*, 7> names{"separated", "compliance", "contact", "stick",
                                                "slip+",     "slip-",      "slip"};
  return names;
}

void count_status(StatusCounts& c, const NodeStatus& s) {
  ++c[static_cast<size_t>(s.normal)];  // NormalStatus: SEPARATED, COMPLIANCE, CONTACT
  static const size_t tangential[] = {3, 4, 5, 6};  // STICK, SLIP_PLUS, SLIP_MINUS, SLIP
  ++c[tangential[static_cast<size_t>(s.tangential)]];
}

std::map<std::string, int> count_map(const StatusCounts& c) {
  std::map<std::string, int> out;
  for (size_t i = 0; i < c.size(); ++i)
    if (i + 1 < c.size() || c[i] > 0) out[status_count_names()[i]] = static_cast<int>(c[i]);
  return out;
}

}  // namespace hemicontact
