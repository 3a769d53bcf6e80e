#include <hemicontact/problem/solve_options.hpp>

namespace hemicontact {

std::vector<std::pair<double, double>> smoothing_schedule(const SolveOptions& o) {
  std::vector<std::pair<double, double>> schedule;
  // A width within 1e-9 (relative) of the final one counts as final: 1e-2·(1e-2)⁴ is not 1e-10
  // in floating point, and a stage that repeats the final width would only cost time.
  const auto at_final = [](double e, double fin) { return e <= fin * (1 + 1e-9); };
  for (double e = o.eps_start;; e *= o.eps_factor) {
    const double et = at_final(e, o.eps_tau) ? o.eps_tau : e;
    const double en = at_final(e, o.eps_nu) ? o.eps_nu : e;
    schedule.emplace_back(et, en);
    if (et == o.eps_tau && en == o.eps_nu) break;
  }
  return schedule;
}

}  // namespace hemicontact
