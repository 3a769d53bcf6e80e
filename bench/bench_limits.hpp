#pragma once
// The ranges of the bench programs' counts, one home for all of them (random_study, stress_report,
// backends, whole_process, adapt_study): a value beyond one is a typo that would run for days, and
// is refused as a usage error (core/options.hpp) rather than started.

namespace hemicontact::bench {

inline constexpr long MAX_REPEATS = 100;     ///< each timing best of at most this many runs
inline constexpr long MAX_SEEDS = 1000000;   ///< random scenes per study
inline constexpr long MAX_MESH_N = 4096;     ///< cells across a generated mesh (mesh.n)
inline constexpr long MAX_ITERATIONS = 1000000;  ///< an outer iteration cap (stress_report --max-iter)

}  // namespace hemicontact::bench
