#include <hemicontact/core/interrupt.hpp>

namespace hemicontact {
namespace {
// Per thread: solves in several threads of one host each answer to their own check.
thread_local const std::function<bool()>* t_check = nullptr;
thread_local bool t_requested = false;
}  // namespace

ScopedInterruptCheck::ScopedInterruptCheck(std::function<bool()> check)
    : m_check(std::move(check)), m_previous(t_check), m_previous_requested(t_requested) {
  t_check = m_check ? &m_check : nullptr;
  t_requested = false;
}

ScopedInterruptCheck::~ScopedInterruptCheck() {
  t_check = m_previous;
  t_requested = m_previous_requested;
}

bool interrupt_requested() {
  if (t_check == nullptr) return false;
  // Sticky: a check that consumes its signal (Python's PyErr_CheckSignals) is asked only once.
  if (!t_requested && (*t_check)()) t_requested = true;
  return t_requested;
}

}  // namespace hemicontact
