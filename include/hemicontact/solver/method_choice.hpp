#pragma once
/// @file method_choice.hpp  solver.formulation = auto: the method from the scene's own numbers,
/// decided before any numeric work (issue: "skip what a scene doesn't need" applies to methods).
///
/// The two methods of the cholmod engine for a linear material with a Γ3:
///   condensed  one sparse factorization of K with the m = d·n_Γ3 Γ3 unknowns last (CHOLMOD's
///              predicted flops fl_C, which include the dense m × m trailing block's m³/3), then the
///              dense Schur complement S, the exact solver and the polish on Γ3: dense_work · m³;
///              and ~7 dense m × m matrices in memory;
///   full       all free unknowns, the continuation with a projected Newton (CHOLMOD) backend:
///              full_factorizations · fl_F, fl_F the flops of the factorization without the Γ3
///              block (a second symbolic analysis, same ordering rule, made only when needed).
/// In order: the dense matrices do not fit in memory_fraction of the memory available → full;
/// dense_work · m³ ≤ small_fraction · fl_C → condensed (the paper's 2D scenes: no second analysis);
/// fl_C + dense_work · m³ ≤ condensed_below, and not above full_cheaper_by · full_factorizations ·
/// fl_F → condensed (small scenes keep the exact path, but a long strip's dense work is its whole
/// cost; where fl_F's lower bound from K's pattern already decides it, fl_F is not analysed);
/// otherwise condensed iff fl_C + dense_work · m³ ≤ full_factorizations · fl_F. The analysis of the
/// condensation is its own, which the condensed path then factorizes without analysing again. The
/// cores do not enter: the supernodal factorization and the dense Γ3 work are both BLAS-3 and
/// scale alike.
/// Under the full choice, solver.backend = auto resolves to ssn, the full space's exact solver
/// (solver/ssn.hpp): on the fig2 strip 1000 × 1 ssn took 0.04 s (certificate 6e-16), the newton
/// backend's continuation 0.24 s (5e-13) and ipopt's 2.3 s (the same energy).

#include <hemicontact/problem/reports.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <functional>
#include <string>

namespace hemicontact {

/// What the choice reads of a scene.
struct SceneNumbers {
  int dim = 2;
  Index dofs = 0;             ///< free unknowns
  Index gamma3_unknowns = 0;  ///< m = d · Γ3 nodes
  bool linear_material = true;
  double factor_nnz = 0;    ///< nnz(L) predicted by CHOLMOD's analysis (Γ3 last)
  double factor_flops = 0;  ///< fl_C: flops of the condensation's numeric factorization, predicted likewise
  double full_factor_flops = 0;  ///< fl_F: the full formulation's factorization (0: not analysed yet)
  double full_factor_flops_low = 0;  ///< a lower bound of fl_F from K's own pattern (factor_flops_lower_bound)
  double memory_bytes = 0;  ///< memory available to the process
  int cores = 1;            ///< hardware threads (reported; see the file comment)
};

/// A lower bound of any Cholesky factorization's flops Σ_j c_j² for the symmetric matrix whose lower
/// triangle is @p lower, under any ordering: L's column counts c_j contain the permuted matrix's, so
/// Σ_j c_j ≥ nnz(lower), and Σ_j c_j² ≥ (Σ_j c_j)²/n (Cauchy–Schwarz). No analysis: nnz and n.
double factor_flops_lower_bound(const SpMat& lower);

/// The memory this process may still use: physical memory available (/proc/meminfo MemAvailable),
/// or the address-space limit less what the process maps, where lower.
double available_memory_bytes();

/// The choice for @p n under @p opt (solver.formulation, solver.backend, solver.method_choice):
/// an explicit formulation is kept (and a condensed one for a nonlinear material refused by the
/// caller); auto decides by the rule of the file comment. reason and numbers say why.
/// @param full_flops analyses the full formulation's factorization and returns fl_F, called only
/// when the rule needs it (null: n.full_factor_flops as given).
MethodChoice choose_method(const SceneNumbers& n, const SolveOptions& opt,
                           const std::function<double()>& full_flops = nullptr);

/// The choice's line for stdout and the summary: "condensed (auto): <reason>".
std::string describe(const MethodChoice& c);

}  // namespace hemicontact
