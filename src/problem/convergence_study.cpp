// The convergence study's record: its verdict and the reference-corrected rate fit
// (convergence_study.hpp), computed from the record alone.
#include <hemicontact/problem/convergence_study.hpp>

#include <hemicontact/core/format.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

namespace hemicontact {

bool ConvergenceStudy::ok() const { return failed().empty(); }

std::vector<int> ConvergenceStudy::failed() const {
  std::vector<int> f;
  for (const auto& l : levels)
    if (!l.ok) f.push_back(l.n);
  if (!reference.ok && std::find(f.begin(), f.end(), reference.n) == f.end()) f.push_back(reference.n);
  return f;
}

RateFit fit_rate(const ConvergenceStudy& study, int max_levels) {
  const double hR = study.reference.h;
  std::vector<double> h, e;
  for (const auto& l : study.levels)
    if (l.error > 0 && l.h > hR && l.other_branch.empty()) {
      h.push_back(l.h);
      e.push_back(l.error);
    }
  const size_t m = std::min(h.size(), static_cast<size_t>(std::max(max_levels, 2)));
  RateFit fit;
  if (m < 2) return fit;
  h.erase(h.begin(), h.end() - static_cast<std::ptrdiff_t>(m));
  e.erase(e.begin(), e.end() - static_cast<std::ptrdiff_t>(m));
  // For fixed α the optimal log C is the mean log residual; the remaining 1-D least-squares
  // problem in α is scanned on a grid, then refined by golden-section search in the best cell.
  const auto log_c = [&](double a) {
    double s = 0;
    for (size_t i = 0; i < m; ++i) s += std::log(e[i]) - 0.5 * std::log(std::pow(h[i], 2 * a) - std::pow(hR, 2 * a));
    return s / m;
  };
  const auto sse = [&](double a) {
    const double lc = log_c(a);
    double s = 0;
    for (size_t i = 0; i < m; ++i) {
      const double r = std::log(e[i]) - lc - 0.5 * std::log(std::pow(h[i], 2 * a) - std::pow(hR, 2 * a));
      s += r * r;
    }
    return s;
  };
  const double lo = 0.05, hi = 4.0, step = 0.01;
  double best = lo;
  for (double a = lo; a <= hi; a += step)
    if (sse(a) < sse(best)) best = a;
  double a = std::max(lo, best - step), b = std::min(hi, best + step);
  const double phi = 0.5 * (std::sqrt(5.0) - 1);
  for (int it = 0; it < 60; ++it) {
    const double x1 = b - phi * (b - a), x2 = a + phi * (b - a);
    if (sse(x1) < sse(x2))
      b = x2;
    else
      a = x1;
  }
  fit.alpha = 0.5 * (a + b);
  fit.C = std::exp(log_c(fit.alpha));
  fit.levels_used = static_cast<int>(m);
  for (size_t i = 0; i < m; ++i) {
    const double model = fit.C * std::sqrt(std::pow(h[i], 2 * fit.alpha) - std::pow(hR, 2 * fit.alpha));
    fit.max_rel_residual = std::max(fit.max_rel_residual, std::abs(model / e[i] - 1));
  }
  fit.valid = true;
  return fit;
}

namespace {

// Level i's error over the fit of the other unflagged levels (NaN where they do not fit).
double off_the_others(const ConvergenceStudy& study, size_t i) {
  const ConvergenceLevel& l = study.levels[i];
  const double hR = study.reference.h;
  if (!(l.error > 0 && l.h > hR) || !l.other_branch.empty()) return NaN;
  ConvergenceStudy others = study;  // leave this level out
  others.levels.erase(others.levels.begin() + static_cast<std::ptrdiff_t>(i));
  const RateFit fit = fit_rate(others);
  if (!fit.valid) return NaN;
  return l.error / (fit.C * std::sqrt(std::pow(l.h, 2 * fit.alpha) - std::pow(hR, 2 * fit.alpha)));
}

}  // namespace

std::vector<int> flag_other_branches(ConvergenceStudy& study, const BranchCheck& check) {
  bool doubt = study.reference.unique_in_doubt;
  for (const auto& l : study.levels) doubt = doubt || l.unique_in_doubt;
  std::vector<int> flagged;
  if (!doubt) return flagged;
  // One level at a time, the farthest off first: a level on another branch tilts the fit of the
  // others, and would make a good neighbour look off too.
  for (;;) {
    size_t worst = study.levels.size();
    double worst_off = std::log(check.error_factor), ratio = NaN;
    for (size_t i = 0; i < study.levels.size(); ++i) {
      const double r = off_the_others(study, i);
      if (std::isfinite(r) && std::abs(std::log(r)) > worst_off) worst = i, worst_off = std::abs(std::log(r)), ratio = r;
    }
    if (worst == study.levels.size()) return flagged;
    study.levels[worst].other_branch =
        "error " + fmt(ratio, 3) + " x the fit of the other levels (beyond a factor " + fmt(check.error_factor, 3) +
        "): taken to lie on another branch (uniqueness is not guaranteed here); left out of the rate fit";
    flagged.push_back(study.levels[worst].n);
  }
}

}  // namespace hemicontact
