// The minima report's counts (minima_report.hpp), from the record alone.
#include <hemicontact/problem/minima_report.hpp>

#include <algorithm>

namespace hemicontact {

int MinimaReport::local_minima() const {
  return static_cast<int>(std::count_if(solutions.begin(), solutions.end(), [](const DistinctSolution& d) {
    return d.second_order.verdict == "local minimum";
  }));
}

int MinimaReport::certified_runs() const {
  return static_cast<int>(std::count_if(runs.begin(), runs.end(), [](const MinimaRun& r) { return r.certified; }));
}

}  // namespace hemicontact
