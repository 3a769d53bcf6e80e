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

}  // namespace hemicontact
