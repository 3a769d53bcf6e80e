#pragma once
/// @file adapt_options.hpp  The options of the adaptive loop (solver/adapt.hpp), in one home: the
/// scene schema (scene/scene_schema.cpp) reads its defaults from this struct, so that a default is
/// written once. It lives beside the estimator it configures, below scene/ and solver/ (both read it).

#include <hemicontact/check/estimator.hpp>
#include <hemicontact/core/types.hpp>
#include <hemicontact/mesh/bisection.hpp>

#include <limits>

namespace hemicontact {

/// The scene's `adapt` block (docs/scene-format.md). target_error is the default target of a run
/// that asks for adaptation without naming one (`converge --adaptive`); in a scene, adapt.target_error
/// = null (the schema's default) means no adaptation.
struct AdaptOptions {
  double target_error = 0.01;  ///< stop once the relative estimate η/‖u_h‖_E is at or below this
  Index max_dofs = 400000;     ///< never solve a mesh with more free unknowns than this
  int max_levels = 30;         ///< at most this many meshes (the first included)
  double theta = 0.5;          ///< Dörfler bulk parameter θ ∈ (0, 1]
  /// The last step's size (0: off, else ≥ 1). Adaptive P1 meshes follow η ≈ C N^(−1/2) (on the
  /// fig2 scene η√N = 3.42–3.47 over levels 6–12), so the target needs about
  /// N* = N (η/target)² unknowns. When Dörfler's marking would give a next mesh of more than
  /// landing · N* nodes, only the largest indicators are marked (mark_largest, a subset of
  /// Dörfler's set), as many as should give about landing · N*. The margin (10 %: η√N varies by
  /// ±1 % over the fine levels, the node count of a cut marking is off by a few %) is there
  /// because a step that misses the target costs a further level. Without it, a sequence that stops
  /// just short of the target doubles N once more (fig2 from n = 64: 107k unknowns at 1.08 %,
  /// then 190k).
  double landing = 1.1;
  /// At most this many refinement steps between two solves (1: a solve after every step). The
  /// steps after the first mark predicted indicators (a child of measure ratio r to its parent gets
  /// η_parent² r^(1 + 2/d), the decrease of a smooth solution's η_T²) and stop early when the mesh
  /// is predicted to reach the target (N ≥ N (η/target)^d) or the landing cuts a step. The skipped
  /// solves would only have fed the next marking: fig2 reaches 1 % in 7 levels from n = 8 (12
  /// with 1) on meshes of the same quality (η√N 3.41 against 3.43; docs/adaptivity.md §5). Only
  /// with landing on (the prediction is the landing's rate).
  int lookahead = 2;
  /// OpenBLAS threads during the loop (restored after it; 0: leave the BLAS as configured; an
  /// OPENBLAS_NUM_THREADS in the environment wins). The levels' 2D factorizations have small
  /// supernodes, where BLAS threads only synchronize: on a 2-core machine the fig2 run to 1 % took
  /// 1.42 s CPU / 1.47 s wall with OpenBLAS's default 2 threads and 0.90 / 0.98 s with 1. No effect
  /// with another BLAS (the OpenBLAS entry points are looked up at run time).
  int blas_threads = 1;
  /// The exact solution's energy Π(u) when known (NaN: not known). Galerkin's error in the energy
  /// is of second order: Π(u_h) − Π(u) ≈ ½ ‖u − u_h‖²_E (exact for a quadratic energy; the contact
  /// terms are the small non-quadratic part), so each level reports sqrt(2 (Π(u_h) − Π(u))) / ‖u_h‖_E.
  double reference_energy = std::numeric_limits<double>::quiet_NaN();
  EstimatorKind estimator = EstimatorKind::ZZ;
  BisectionRule bisection = BisectionRule::BISEC3;
};

}  // namespace hemicontact
