#include <hemicontact/problem/solution.hpp>

namespace hemicontact {

std::map<std::string, int> Solution::status_counts() const { return count_map(counts); }

SolverWork Solution::work_of(const std::string& solver) const {
  SolverWork w;
  for (const auto& h : history)
    if (h.solver == solver) {
      ++w.minimizations;
      w.iterations += h.backend.iterations;
      w.evaluations += h.backend.evaluations;
      w.seconds += h.backend.seconds;
    }
  return w;
}

std::string Solution::solved_by() const {
  if (formulation.empty()) return "linear";
  const bool nlp = work_of(backend).minimizations > 0;
  const bool exact = handover.used;
  if (nlp && exact) return backend + "+" + EXACT_SOLVER;
  if (exact) return EXACT_SOLVER;
  // The polish solves the unsmoothed conditions on the backend's statuses: its answer is the polish's.
  if (nlp && polish.accepted) return backend + "+polish";
  return backend;
}

}  // namespace hemicontact
