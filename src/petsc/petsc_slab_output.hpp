#pragma once
/// @file petsc_slab_output.hpp  The distributed path's result files (petsc_slab_output.cpp):
/// a piece per rank, the .pvtu and report.json from reductions and the gathered Γ3 rows. Only hemicontact-mpi includes it.

#include "petsc_engine.hpp"

#include <hemicontact/output/output_dir.hpp>

#include <functional>
#include <string>
#include <vector>

namespace hemicontact::petsc_engine {

/// @return the numbered names of the pieces (prepare_output_dir's patterns).
std::vector<OutputNamePattern> slab_output_patterns();

/// @brief Write the pieces (every rank), then solution.pvtu and report.json (rank 0) into the
/// folder @p dir that rank 0 prepared (collective). The owned Γ3 rows are gathered to rank 0 for
/// report.json's "nodes" (a surface's worth); each rank's CSV holds its owned rows only. @p md's
/// cells are swapped for its owned ones while its piece is written, and put back.
/// @param before_report run on rank 0 once the pieces and the .pvtu are written, before report.json
///        (the picture, whose file the report then lists); may be empty
/// @throws Error (EXIT_OUTPUT) on every rank when a rank could not write its files
void write_slab_results(const std::string& dir, const nlohmann::json& scene, const Model& md, const Piece& slab,
                        const Solution& sol, const SlabResult& out, const SolveOptions& opt, const EngineReport& er,
                        MPI_Comm comm, const std::function<void()>& before_report);

/// @brief --stream: no files, report.json's content (as write_slab_results makes it, "files"
/// empty) as one line on stdout, then the whole mesh's displacement as raw float64 (native byte
/// order, node-major, in the whole mesh's node numbering: the report's "node", which the cholmod
/// engine's mesh shares), rank 0 writing both after gathering the owned nodes' u (collective).
/// For a caller that holds the whole model (studies/petsc_process.hpp runs this on one rank).
/// @throws Error on every rank: EXIT_OUTPUT where stdout refused the bytes, EXIT_INTERNAL where a
///         node had no owner
void stream_slab_results(const nlohmann::json& scene, const Model& md, const Piece& slab, const Solution& sol,
                         const SlabResult& out, const SolveOptions& opt, const EngineReport& er, MPI_Comm comm);

}  // namespace hemicontact::petsc_engine
