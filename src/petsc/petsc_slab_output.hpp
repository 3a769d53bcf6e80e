#pragma once
/// @file petsc_slab_output.hpp  The distributed path's result files (petsc_slab_output.cpp):
/// a piece per rank, the .pvtu and report.json from reductions. Only hemicontact-mpi includes it.

#include "petsc_engine.hpp"

#include <hemicontact/output/output_dir.hpp>

#include <string>
#include <vector>

namespace hemicontact::petsc_engine {

/// @return the numbered names of the pieces (prepare_output_dir's patterns).
std::vector<OutputNamePattern> slab_output_patterns();

/// @brief Write the pieces (every rank), then solution.pvtu and report.json (rank 0) into the
/// folder @p dir that rank 0 prepared (collective). @p md's cells are swapped for its owned ones
/// while its piece is written, and put back.
/// @throws Error (EXIT_OUTPUT) on every rank when a rank could not write its files
void write_slab_results(const std::string& dir, const nlohmann::json& scene, Model& md, const Slab& slab,
                        const Solution& sol, const SlabResult& out, const SolveOptions& opt, const EngineReport& er,
                        MPI_Comm comm);

}  // namespace hemicontact::petsc_engine
