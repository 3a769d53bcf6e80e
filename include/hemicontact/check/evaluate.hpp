#pragma once
/// @file evaluate.hpp  What a displacement is worth on the unsmoothed problem (22): its Γ3 state,
/// statuses, certificate (docs/model.md §4) and energies. The solve, the polish and the studies all
/// judge a candidate with this one function; the petsc engine's pieces with apply_judgement.

#include <hemicontact/check/judge.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

namespace hemicontact {

/// Unsmoothed energy parts and certificate of a given full displacement (fills the Solution's
/// state, status, certificate and energies).
void evaluate_solution(const Model& model, const SolveOptions& options, Solution& sol);

/// The same for a linear material with @p Kx_x = K_x x (x the reduced sol.u) given by the caller:
/// an engine that keeps K itself (the petsc engine's model keeps no K_x).
void evaluate_solution(const Model& model, const SolveOptions& options, Solution& sol, const Vec& Kx_x);

/// The judge (check/judge.hpp) over @p scope with @p reduce, of sol.u and sol.state (already set),
/// into sol: certificate, statuses, Γ3 energy terms, max u_ν, status counts.
void apply_judgement(const Model& model, const SolveOptions& options, Solution& sol, const JudgeScope& scope,
                     const Reduction& reduce);

}  // namespace hemicontact
