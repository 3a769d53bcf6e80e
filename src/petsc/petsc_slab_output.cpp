// The distributed path's results: every rank writes its own piece (solution_rank<r>.vtu of its
// owned cells, gamma3_rank<r>.csv of its slab's Γ3 nodes), rank 0 the .pvtu that lists them and
// report.json, whose every number is a reduction: no process gathers the solution.
#include "petsc_slab_output.hpp"

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/output/csv_writer.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/pvtu_writer.hpp>
#include <hemicontact/output/solve_files.hpp>
#include <hemicontact/output/vtk_writer.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hemicontact::petsc_engine {

namespace {

std::string piece_name(const char* prefix, int rank, const char* suffix) {
  return prefix + std::to_string(rank) + suffix;
}

// This rank's piece: the VTU of its owned cells (the ghost layer is the rank below's), and the CSV
// of its slab's Γ3 nodes (a ghost's row repeats its owner's, computed from the same rows of x).
void write_piece(const std::string& dir, const nlohmann::json& scene, Model& md, const Slab& slab,
                 const SlabResult& out, int rank) {
  const std::filesystem::path p(dir);
  if (scene.at("output").at("vtu").get<bool>()) {
    IMat owned(static_cast<Index>(std::count(slab.owned_cell.begin(), slab.owned_cell.end(), 1)), md.mesh.cells.cols());
    for (Index c = 0, r = 0; c < md.mesh.num_cells(); ++c)
      if (slab.owned_cell[static_cast<size_t>(c)]) owned.row(r++) = md.mesh.cells.row(c);
    std::swap(owned, md.mesh.cells);
    const VtuFormat f = scene.at("output").at("vtu_format").get<std::string>() == "ascii" ? VtuFormat::ASCII : VtuFormat::BINARY;
    try {
      write_vtu((p / piece_name("solution_rank", rank, ".vtu")).string(), md, out.piece, f);
    } catch (...) {
      std::swap(owned, md.mesh.cells);
      throw;
    }
    std::swap(owned, md.mesh.cells);
  }
  if (scene.at("output").at("csv").get<bool>())
    write_gamma3_csv((p / piece_name("gamma3_rank", rank, ".csv")).string(), md, out.piece);
}

nlohmann::json certificate_record(const CertificateReport& c) {
  nlohmann::json residuals = nlohmann::json::object();
  for (const auto& e : c.residuals) residuals[e.name] = {{"value", e.value}, {"worst_petsc_row", e.worst}};
  return {{"passed", c.passed},           {"tol", c.tol},
          {"max_residual", c.max_residual}, {"length_scale", c.length_scale},
          {"force_scale", c.force_scale},   {"traction_scale", c.traction_scale},
          {"residuals", std::move(residuals)}};
}

// report.json of the distributed path: make_report's keys that reductions give (no "nodes": the
// Γ3 nodes are in the pieces, "pieces" names them).
nlohmann::json slab_report(const nlohmann::json& scene, const Model& md, const Solution& sol, const SlabResult& out,
                           const Slab& slab, const SolveOptions& opt, const EngineReport& er, double h, int size) {
  nlohmann::json r;
  r["scene"] = scene;
  r["version"] = HEMICONTACT_VERSION;
  r["engine"] = "petsc";
  r["mesh"] = {{"origin", md.mesh.origin}, {"dim", md.dim()}, {"nodes", slab.global_nodes},
               {"cells", slab.global_cells}, {"gamma3_nodes", out.gamma3_nodes}, {"h", h}};
  r["dofs"] = er.json.value("unknowns", 0L);
  r["material"] = {{"description", md.material->describe()}, {"is_linear", md.material->is_linear()}};
  r["laws"] = {{"normal_law", md.normal_law ? nlohmann::json(md.normal_law->describe()) : nlohmann::json(nullptr)},
               {"friction", md.friction ? nlohmann::json(md.friction->describe()) : nlohmann::json(nullptr)},
               {"gap", md.gap.describe()}};
  const SolverWork bt = sol.work_of(sol.backend);
  r["backend"] = {{"name", sol.backend}, {"requested", sol.backend_use.requested}, {"ran", sol.backend_use.ran},
                  {"iterations", bt.iterations}, {"seconds", bt.seconds}};
  for (const auto& [k, v] : std::vector<std::pair<const char*, double>>{
           {"energy", sol.energy}, {"energy_norm", sol.energy_norm}, {"a_uu", sol.a_uu},
           {"elastic_energy", sol.elastic_energy}, {"f_u", sol.f_u}, {"j_term", sol.j_term},
           {"friction_term", sol.friction_term}, {"max_u_nu", sol.max_u_nu}})
    r[k] = v;
  r["status_counts"] = out.status_counts;
  r["certificate"] = certificate_record(sol.certificate);
  r["options"] = {{"backend", opt.backend}, {"certificate_tol", opt.certificate_tol}, {"status_tol", opt.status_tol}};
  r["skipped"] = sol.skipped;
  r["formulation"] = sol.formulation;
  r["scales"] = {{"x_scale", sol.x_scale}, {"f_scale", sol.f_scale}};
  nlohmann::json t = nlohmann::json::object();
  for (const auto& [k, v] : md.timings) t[k] = v;  // rank 0's slab
  for (const auto& [k, v] : sol.timings) t[k] = v;
  r["timings"] = t;
  r["petsc"] = er.json;
  std::vector<std::string> vtu, csv;
  for (int q = 0; q < size; ++q) {
    if (scene.at("output").at("vtu").get<bool>()) vtu.push_back(piece_name("solution_rank", q, ".vtu"));
    if (scene.at("output").at("csv").get<bool>()) csv.push_back(piece_name("gamma3_rank", q, ".csv"));
  }
  r["pieces"] = {{"vtu", vtu}, {"gamma3_csv", csv}};
  r["message"] = sol.message;
  r["ok"] = sol.ok();
  return r;
}

}  // namespace

std::vector<OutputNamePattern> slab_output_patterns() {
  return {{"solution_rank", ".vtu"}, {"gamma3_rank", ".csv"}};
}

void write_slab_results(const std::string& dir, const nlohmann::json& scene, Model& md, const Slab& slab,
                        const Solution& sol, const SlabResult& out, const SolveOptions& opt, const EngineReport& er,
                        MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const double h_mine = md.mesh.max_edge_length();
  double h = 0;
  MPI_Allreduce(&h_mine, &h, 1, MPI_DOUBLE, MPI_MAX, comm);
  const std::filesystem::path p(dir);
  // The pieces' names are in the manifest before any is created (rank 0 alone appends to it), so
  // that --force after a crash knows every file; then each rank writes its own.
  int code = 0;
  std::string message;
  const auto attempt = [&](const auto& fn) {
    if (code != 0) return;
    try {
      fn();
    } catch (const Error& e) {
      code = e.code();
      message = e.what();
    }
  };
  if (rank == 0)
    attempt([&] {
      for (int q = 0; q < size; ++q) {
        if (scene.at("output").at("vtu").get<bool>()) record_output_file((p / piece_name("solution_rank", q, ".vtu")).string());
        if (scene.at("output").at("csv").get<bool>()) record_output_file((p / piece_name("gamma3_rank", q, ".csv")).string());
      }
    });
  MPI_Bcast(&code, 1, MPI_INT, 0, comm);
  attempt([&] { write_piece(dir, scene, md, slab, out, rank); });
  int worst = 0;
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, comm);
  if (worst != 0) {
    if (code != 0) std::fprintf(stderr, "hemicontact: error (rank %d): %s\n", rank, message.c_str());
    throw Error("the results could not be written (see the ranks' messages above)", static_cast<ExitCode>(worst));
  }
  if (rank == 0)
    attempt([&] {
      std::vector<std::string> pieces;
      for (int q = 0; q < size && scene.at("output").at("vtu").get<bool>(); ++q)
        pieces.push_back(piece_name("solution_rank", q, ".vtu"));
      if (!pieces.empty()) write_pvtu((p / "solution.pvtu").string(), md.dim(), pieces);
      write_final_report(dir, slab_report(scene, md, sol, out, slab, opt, er, h, size));
      std::printf("results in %s (%d pieces)\n", dir.c_str(), size);
    });
  MPI_Bcast(&code, 1, MPI_INT, 0, comm);
  if (code != 0) throw Error(rank == 0 ? message : "rank 0 could not write the results", static_cast<ExitCode>(code));
}

}  // namespace hemicontact::petsc_engine
