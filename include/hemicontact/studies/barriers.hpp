#pragma once
/// @file barriers.hpp  Energy barriers between distinct local minima (`hemicontact minima --barriers`):
/// the minimum-energy path between two minima by the string method, its highest point refined to
/// an exact saddle and verified.
///
/// Where: the condensed Γ3 unknowns x (docs/model.md §2), on the energy with the friction bound λ
/// frozen,
///     Φ_λ(x) = ½ (x − y)ᵀ S (x − y) + Σ_k w_k j_ν(x_ν,k) + Σ_k w_k λ_k |x_τ,k|,  x_ν,k ≤ g_k,
/// plus the constant −½ fᵀy, so that Φ_λ(x) is the energy Π of the state x. Frictionless and
/// Tresca scenes (λ independent of u) are exact: Φ_λ is their energy. For the Coulomb-type bound
/// λ = F_b(u_ν) is frozen at each minimum's own λ, and the barrier from each side is computed on
/// that side's Φ_λ (the far minimum first relaxed on it by the exact solver's local descent); the
/// report says which λ each side used.
///
/// The string (E, Ren, Vanden-Eijnden, J. Chem. Phys. 126, 2007, the simplified string method):
/// M + 1 images from minimum a to minimum b, each step a proximal-gradient step of Φ_λ on the
/// interior images (gradient of the smooth part ½(x−y)ᵀS(x−y) + Σ w j_ν, step 1/L with L an upper
/// bound of its curvature; the proximal map of w λ |x_τ| (soft threshold) and the projection on
/// x_ν ≤ g), then the images are spaced equally in arc length again; until the images move by less
/// than BarrierOptions::string_tol. j_ν must be C¹ (p_ν continuous): a law with jumps has no
/// gradient at them, and the string is not run (said so).
///
/// Chains: a converged string whose energy profile has an interior local minimum runs through
/// another minimum's basin; that image is relaxed to the minimum (the exact solver's local
/// descent) and the path is computed again segment by segment (to BarrierOptions::max_depth
/// levels), each segment's saddle refined: the barrier of the pair is the highest saddle on the
/// chain, and the pair is reported as not neighbouring (with the number of intermediate minima).
/// The string converges to a minimum-energy path near its start (the straight segment): the lowest
/// pass between two minima may lie on another path, through a third minimum.
///
/// The saddle: the highest image's branch signature (each node's piece of p_ν or the bound g, and
/// stick or slip direction) makes the stationarity conditions of Φ_λ linear (2D); their solution
/// is the exact stationary point on that signature. It is verified: it lies on its signature,
/// its stationarity residual (exact_inner_residual) is at round-off (≤ saddle_tol), and the
/// Hessian S + diag(w_k p_ν'(x_ν,k)) on the free subspace (contact ν and sticking τ removed) has
/// exactly one negative eigenvalue. The signatures of the neighbouring images are tried when the
/// highest one's is not verified. 2D only (3D slip directions make the conditions nonlinear).

#include <hemicontact/problem/minima_report.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <string>
#include <vector>

namespace hemicontact {

/// What find_barriers() does; defaults are the ones `minima --barriers` documents.
struct BarrierOptions {
  int minima = 3;      ///< the lowest this many distinct local minima, every pair of them
  int images = 31;     ///< M + 1 images on the string, the two minima included
  /// The string has converged when no image moved by more than this × max|x| in a step: 1e-9,
  /// where the highest image is close enough for its signature to be the saddle's.
  double string_tol = 1e-9;
  int max_steps = 200000;  ///< string steps at most
  /// A refined saddle is verified when its stationarity residual (exact_inner_residual, traction
  /// units) is at most this: 1e-9, round-off of the linear solve at these condition numbers.
  double saddle_tol = 1e-9;
  int max_depth = 6;  ///< levels of splitting a path at intermediate minima
  /// Relative round-off of energies and eigenvalues: an interior image counts as a local minimum
  /// of the profile when it is below both neighbours by more than this × the ends' |Π|, and an
  /// eigenvalue as negative when below −this × the largest |eigenvalue|. 1e-12: a few hundred ulps.
  double round_off = 1e-12;
};

/// One side of a barrier: the energy with λ frozen at that side's minimum.
struct BarrierSide {
  int minimum = -1;           ///< index into MinimaReport::solutions
  std::string lambda;         ///< "none (frictionless)", "Tresca (independent of u)", or "frozen at minimum k"
  double energy_min = 0;      ///< Π of the minimum on this side's Φ_λ
  double energy_saddle = 0;   ///< Π of the highest saddle on the path
  double barrier = 0;         ///< energy_saddle − energy_min
  bool verified = false;      ///< the saddle passed every check
  /// false when the path runs through intermediate minima (the two are not neighbours; the
  /// barrier is then the highest saddle on the chain)
  bool neighbours = true;
  int intermediate = 0;          ///< intermediate minima the path runs through
  std::vector<double> saddles;   ///< the energy of every segment's saddle, in path order
  bool all_verified = true;      ///< every segment's saddle verified (working value of `verified`)
  std::string note;           ///< why not verified, or remarks
  double residual = 0;        ///< the saddle's stationarity residual
  int negative = 0;           ///< negative eigenvalues of its reduced Hessian
  Vec saddle;                 ///< the saddle's Γ3 unknowns (d per node)
  std::vector<double> profile;  ///< Φ_λ along the converged string, image by image
  int steps = 0;              ///< string steps taken
};

/// The barrier between two minima a < b (energies ascending): one side per minimum.
struct Barrier {
  int a = -1, b = -1;
  BarrierSide from_a, from_b;
};

/// @throws Error (EXIT_INPUT) where barriers do not apply: a 3D model, or a p_ν that jumps downward.
void require_barrier_scene(const Model& md);

/// Every barrier between the lowest BarrierOptions::minima local minima of @p R.
/// @throws Error (EXIT_INPUT) for a 3D model, or bad options
std::vector<Barrier> find_barriers(const Model& md, const SolveOptions& opt, const MinimaReport& R,
                                   const BarrierOptions& bo);

/// A Solution (state, statuses, certificate, energies) for the Γ3 unknowns @p x, the interior
/// recovered by one solve: for the saddle's VTU.
Solution state_of_gamma3(const Model& md, const SolveOptions& opt, const Vec& x);

}  // namespace hemicontact
