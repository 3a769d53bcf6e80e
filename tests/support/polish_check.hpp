#pragma once
/// @file polish_check.hpp  The exact polish was kept, or it was not needed.

#include <hemicontact/problem/solution.hpp>

#include <gtest/gtest.h>

#include <string>

namespace hemicontact::test {

/// Success when the polish ran and was accepted, or when it was skipped because the exact solver's
/// answer was at round-off already (solver.exact.polish_above). Which of the two happens depends on
/// the last bits of the exact solver's coupled residual (1e-16..1e-13), so a test that means "the
/// answer carries no smoothing error" accepts either; the certificate is checked beside it.
inline ::testing::AssertionResult polished_or_at_roundoff(const Solution& s) {
  if (s.polish.attempted && s.polish.accepted) return ::testing::AssertionSuccess();
  for (const auto& k : s.skipped)
    if (k.rfind("polish: the exact solver's coupled residual", 0) == 0) return ::testing::AssertionSuccess() << k;
  return ::testing::AssertionFailure() << "polish " << (s.polish.attempted ? "rejected" : "not attempted")
                                       << " and not skipped at round-off: " << s.polish.note;
}

}  // namespace hemicontact::test
