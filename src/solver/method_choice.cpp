#include <hemicontact/solver/method_choice.hpp>

#include <hemicontact/core/format.hpp>
#include <hemicontact/solver/ssn.hpp>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

namespace hemicontact {
namespace {

// /proc/meminfo's MemAvailable in bytes (0 where it cannot be read).
double meminfo_available() {
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  double kb = 0;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  return 0;
}

// Bytes this process maps now (/proc/self/statm's first field, in pages).
double mapped_bytes() {
  std::ifstream in("/proc/self/statm");
  double pages = 0;
  in >> pages;
  return pages * static_cast<double>(sysconf(_SC_PAGESIZE));
}

// The dense Γ3 matrices of the condensed path: 7 of m × m doubles (solve_options.hpp: memory_fraction).
double dense_bytes(double m) { return 7 * 8 * m * m; }

// The auto decision for a linear material with m > 0 Γ3 unknowns (method_choice.hpp's rule).
void decide(SceneNumbers n, const MethodChoiceOptions& o, const std::function<double()>& full_flops, MethodChoice& c) {
  const double m = static_cast<double>(n.gamma3_unknowns), dense = o.dense_work * m * m * m;
  const double condensed = n.factor_flops + dense;
  const double bytes = dense_bytes(m), budget = o.memory_fraction * n.memory_bytes;
  c.numbers["dense_flops"] = dense;
  c.numbers["condensed_flops"] = condensed;
  c.numbers["dense_bytes"] = bytes;
  const std::string dw = "dense Gamma3 work " + fmt(o.dense_work, 3) + " m^3 = " + fmt(dense, 3) + " flops (m = " +
                         std::to_string(n.gamma3_unknowns) + ")";
  if (n.memory_bytes > 0 && bytes > budget) {
    c.chosen = "full";
    c.reason = "the dense Gamma3 matrices (" + fmt(bytes / 1e9, 3) + " GB) exceed solver.method_choice.memory_fraction " +
               "of the memory available (" + fmt(budget / 1e9, 3) + " GB)";
    return;
  }
  if (dense <= o.small_fraction * n.factor_flops) {
    c.chosen = "condensed";
    c.reason = dw + " <= " + fmt(o.small_fraction, 3) + " x the factorization's " + fmt(n.factor_flops, 3) + " flops";
    return;
  }
  const std::string cw = "condensed work " + fmt(condensed, 3) + " flops (a factorization with the Gamma3 block, " +
                         fmt(n.factor_flops, 3) + ", and the " + dw + ")";
  // full_factorizations · fl_F ≥ full_factorizations · (K's pattern bound): where that bound already
  // leaves the condensed work within full_cheaper_by, fl_F's analysis would not change the answer.
  const double full_low = o.full_factorizations * n.full_factor_flops_low;
  if (condensed <= o.condensed_below && condensed <= o.full_cheaper_by * full_low) {
    c.numbers["full_flops_low"] = full_low;
    c.chosen = "condensed";
    c.reason = cw + " <= solver.method_choice.condensed_below, and the full work >= " + fmt(full_low, 3) +
               " flops (" + fmt(o.full_factorizations, 3) + " factorizations of at least nnz(K)^2/n = " +
               fmt(n.full_factor_flops_low, 3) + ", no analysis needed) is not " + fmt(o.full_cheaper_by, 3) +
               "x less: the exact solver's path, at no real cost";
    return;
  }
  if (full_flops) n.full_factor_flops = full_flops();
  const double full = o.full_factorizations * n.full_factor_flops;
  c.numbers["full_factor_flops"] = n.full_factor_flops;
  c.numbers["full_flops"] = full;
  const std::string fw = "full work " + fmt(full, 3) + " flops (" + fmt(o.full_factorizations, 3) +
                         " factorizations of " + fmt(n.full_factor_flops, 3) + ")";
  if (condensed <= o.condensed_below && condensed <= o.full_cheaper_by * full) {
    c.chosen = "condensed";
    c.reason = cw + " <= solver.method_choice.condensed_below, and the " + fw + " is not " +
               fmt(o.full_cheaper_by, 3) + "x less: the exact solver's path, at no real cost";
    return;
  }
  c.chosen = condensed > full ? "full" : "condensed";
  c.reason = cw + (condensed > full ? " > " : " <= ") + fw;
}

}  // namespace

double factor_flops_lower_bound(const SpMat& lower) {
  const double n = static_cast<double>(lower.cols()), nnz = static_cast<double>(lower.nonZeros());
  return n > 0 ? nnz * nnz / n : 0.0;
}

double available_memory_bytes() {
  double avail = meminfo_available();
  rlimit r{};
  if (getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY) {
    const double room = std::max(0.0, static_cast<double>(r.rlim_cur) - mapped_bytes());
    avail = avail > 0 ? std::min(avail, room) : room;
  }
  return avail;
}

MethodChoice choose_method(const SceneNumbers& n, const SolveOptions& opt, const std::function<double()>& full_flops) {
  MethodChoice c;
  c.numbers = {{"dim", n.dim},
               {"dofs", static_cast<double>(n.dofs)},
               {"gamma3_unknowns", static_cast<double>(n.gamma3_unknowns)},
               {"interior_unknowns", static_cast<double>(n.dofs - n.gamma3_unknowns)},
               {"cores", n.cores}};
  if (n.factor_flops > 0) {
    c.numbers["factor_nnz"] = n.factor_nnz;
    c.numbers["factor_flops"] = n.factor_flops;
  }
  if (n.memory_bytes > 0) c.numbers["memory_bytes"] = n.memory_bytes;
  if (opt.formulation != "auto") {
    c.chosen = opt.formulation;
    c.reason = "solver.formulation = " + opt.formulation + " (set explicitly)";
  } else if (!n.linear_material) {
    c.automatic = true;
    c.chosen = "full";
    c.reason = "nonlinear material: static condensation is exact only for a linear one";
  } else if (n.gamma3_unknowns == 0) {
    c.automatic = true;
    c.chosen = "full";
    c.reason = "no Gamma3 unknowns to condense onto";
  } else {
    c.automatic = true;
    decide(n, opt.method_choice, full_flops, c);
  }
  // The full space's exact solver (method_choice.hpp) where auto chose it for a linear material;
  // for a nonlinear one (no K for ssn) the newton backend's continuation: measured on the Hencky
  // scene (bench/method_choice.py, quiet machine) 0.17 s against ipopt's 0.36 s at n = 64, 0.74
  // against 1.94 s at n = 128, both certified, the same answer.
  if (backend_named(opt))
    c.backend = opt.backend;
  else if (c.automatic && c.chosen == "full" && n.linear_material && n.gamma3_unknowns > 0)
    c.backend = SSN_BACKEND;
  else if (c.automatic && c.chosen == "full" && !n.linear_material)
    c.backend = "newton";
  return c;
}

std::string describe(const MethodChoice& c) {
  return c.chosen + (c.automatic ? " (auto)" : "") + (c.backend.empty() ? "" : ", backend " + c.backend) + ": " +
         c.reason;
}

}  // namespace hemicontact
