#pragma once
/// @file interrupt.hpp  Cooperative interruption of a solve by the program that embeds the library.
///
/// The command-line program is ended by SIGINT itself (output/output_dir.hpp). A host that must
/// survive the interrupt (the Python module: Ctrl-C raises KeyboardInterrupt and the interpreter
/// goes on) cannot end the process, so it installs a check on the thread that runs the solve; the
/// solve's loops poll it between steps (each minimization, each round of the exact solver, each
/// Ipopt or Newton iteration, each NLopt evaluation) and unwind with Interrupted when it says so.
/// Without a check installed a poll is one thread-local load: the CLI's solves are unchanged.
#include <functional>
#include <stdexcept>

namespace hemicontact {

/// Thrown by check_interrupt() when the thread's check asked to stop. Not an Error (and not a
/// std::runtime_error): code that turns a failed run into a recorded failure (a study's level, a
/// minima run) must not swallow it.
class Interrupted : public std::exception {
 public:
  const char* what() const noexcept override { return "hemicontact: solve interrupted"; }
};

/// Installs @p check as the calling thread's interrupt check for the life of this object (and
/// restores the previous one after). The check returns true to stop the solve; it may be called
/// often (the caller rate-limits it if it is costly) and is not called again once it said true.
class ScopedInterruptCheck {
 public:
  explicit ScopedInterruptCheck(std::function<bool()> check);
  ~ScopedInterruptCheck();
  ScopedInterruptCheck(const ScopedInterruptCheck&) = delete;
  ScopedInterruptCheck& operator=(const ScopedInterruptCheck&) = delete;

 private:
  std::function<bool()> m_check;
  const std::function<bool()>* m_previous;
  bool m_previous_requested;
};

/// @return true when the calling thread's check asked to stop (now or at an earlier poll):
/// for loops that must stop without throwing (an Ipopt callback returns false, then the backend
/// calls check_interrupt()).
bool interrupt_requested();

/// @throws Interrupted when interrupt_requested().
inline void check_interrupt() {
  if (interrupt_requested()) throw Interrupted();
}

}  // namespace hemicontact
