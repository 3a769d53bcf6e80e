// The distributed path's results: every rank writes its own piece (solution_rank<r>.vtu of its
// owned cells, gamma3_rank<r>.csv of its owned Γ3 nodes), rank 0 the .pvtu that lists them and
// report.json, whose numbers are reductions apart from the list of Γ3 nodes: a surface's worth of
// rows gathered to rank 0, never the body's solution.
#include "petsc_slab_output.hpp"

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/output/csv_writer.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/contact/contact_nodes.hpp>
#include <hemicontact/output/pvtu_writer.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/output/solve_files.hpp>
#include <hemicontact/output/vtk_writer.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <numeric>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace hemicontact::petsc_engine {

namespace {

std::string piece_name(const char* prefix, int rank, const char* suffix) {
  return prefix + std::to_string(rank) + suffix;
}

// The doubles of a Γ3 row in the gather (its node id travels in a long buffer beside them).
constexpr int ROW_DOUBLES = 17;

void pack(const Gamma3Row& r, std::vector<double>& out) {
  out.insert(out.end(), {r.p[0], r.p[1], r.p[2], r.w, r.g, r.u_nu, r.u_tau, r.sigma_nu, r.sigma_tau, r.xi, r.lambda,
                         double(static_cast<int>(r.status.normal)), double(static_cast<int>(r.status.tangential)),
                         r.slip_dir[0], r.slip_dir[1], r.slip_dir[2], r.slip_angle_deg});
}

Gamma3Row unpack(const double* v, long node) {
  Gamma3Row r;
  r.node = node;
  for (int c = 0; c < 3; ++c) r.p[c] = v[c], r.slip_dir[c] = v[13 + c];
  r.w = v[3], r.g = v[4], r.u_nu = v[5], r.u_tau = v[6], r.sigma_nu = v[7], r.sigma_tau = v[8], r.xi = v[9];
  r.lambda = v[10];
  r.status.normal = static_cast<NormalStatus>(static_cast<int>(v[11]));
  r.status.tangential = static_cast<TangentialStatus>(static_cast<int>(v[12]));
  r.slip_angle_deg = v[16];
  return r;
}

// This rank's owned Γ3 nodes (a ghost is its owner's), named in the whole mesh's numbering.
std::vector<Gamma3Row> owned_rows(const Model& md, const Piece& slab, const Solution& piece) {
  std::vector<Gamma3Row> rows;
  for (Index k = 0; k < md.contact.size(); ++k)
    if (slab.owned_node[static_cast<size_t>(md.contact.node[k])]) {
      rows.push_back(gamma3_row(md, piece, k));
      rows.back().node = slab.global_node[static_cast<size_t>(md.contact.node[k])];
    }
  return rows;
}

// Every rank's owned rows gathered to rank 0 in ContactNodes' order (the cholmod engine's order of
// the whole model's Γ3 nodes); each rank gets back its rows' places in that order (@p index), the
// whole list's index k.
// @return the sorted rows on rank 0, nothing elsewhere.
std::vector<Gamma3Row> gather_rows(const std::vector<Gamma3Row>& mine, int dim, std::vector<long>& index,
                                   MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  std::vector<double> buf;
  std::vector<long> ids;
  for (const Gamma3Row& r : mine) pack(r, buf), ids.push_back(r.node);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<size_t>(size)), at(static_cast<size_t>(size), 0), dcounts, dat;
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  for (int q = 1; q < size; ++q) at[static_cast<size_t>(q)] = at[static_cast<size_t>(q - 1)] + counts[static_cast<size_t>(q - 1)];
  const int total = rank == 0 ? at.back() + counts.back() : 0;
  for (int q = 0; q < size; ++q)
    dcounts.push_back(counts[static_cast<size_t>(q)] * ROW_DOUBLES), dat.push_back(at[static_cast<size_t>(q)] * ROW_DOUBLES);
  std::vector<double> all(static_cast<size_t>(total) * ROW_DOUBLES);
  std::vector<long> all_ids(static_cast<size_t>(total)), place(static_cast<size_t>(total));
  MPI_Gatherv(buf.data(), count * ROW_DOUBLES, MPI_DOUBLE, all.data(), dcounts.data(), dat.data(), MPI_DOUBLE, 0, comm);
  MPI_Gatherv(ids.data(), count, MPI_LONG, all_ids.data(), counts.data(), at.data(), MPI_LONG, 0, comm);
  std::vector<Gamma3Row> rows;
  if (rank == 0) {
    std::vector<size_t> order(static_cast<size_t>(total));
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return gamma3_precedes(&all[a * ROW_DOUBLES], all_ids[a], &all[b * ROW_DOUBLES], all_ids[b], dim);
    });
    for (size_t k = 0; k < order.size(); ++k) {
      rows.push_back(unpack(&all[order[k] * ROW_DOUBLES], all_ids[order[k]]));
      place[order[k]] = static_cast<long>(k);
    }
  }
  index.assign(mine.size(), 0);
  MPI_Scatterv(place.data(), counts.data(), at.data(), MPI_LONG, index.data(), count, MPI_LONG, 0, comm);
  return rows;
}

// This rank's piece: the VTU of its owned cells (the ghost layer is the rank below's), and the CSV
// of its owned Γ3 nodes (each node in one piece only), indexed as in the whole list.
void write_piece(const std::string& dir, const nlohmann::json& scene, const Model& md, const Piece& slab,
                 const SlabResult& out, const std::vector<Gamma3Row>& rows, const std::vector<long>& index, int rank) {
  const std::filesystem::path p(dir);
  if (scene.at("output").at("vtu").get<bool>()) {
    std::vector<Index> owned;
    for (Index c = 0; c < md.mesh.num_cells(); ++c)
      if (slab.owned_cell[static_cast<size_t>(c)]) owned.push_back(c);
    const VtuFormat f = scene.at("output").at("vtu_format").get<std::string>() == "ascii" ? VtuFormat::ASCII : VtuFormat::BINARY;
    write_vtu((p / piece_name("solution_rank", rank, ".vtu")).string(), md, out.piece, f, nullptr, &owned);
  }
  if (scene.at("output").at("csv").get<bool>())
    write_gamma3_csv((p / piece_name("gamma3_rank", rank, ".csv")).string(), md.dim(), rows, index);
}

// The whole mesh's facts from the pieces: the summed sizes, the reduced h and the Γ3 rows gathered
// to rank 0 (in ContactNodes' order), as one process's model gives them (summary_facts).
SummaryFacts slab_facts(const Model& md, const Piece& slab, const Solution& sol, const EngineReport& er, double h,
                        std::vector<Gamma3Row> nodes) {
  SummaryFacts f;
  f.origin = md.mesh.origin;
  f.nodes = slab.global_nodes;
  f.cells = slab.global_cells;
  f.dofs = er.json.value("unknowns", 0L);
  f.h = h;
  f.dim = md.dim();
  f.linear = md.material->is_linear();
  f.rows = std::move(nodes);
  f.timings = md.timings;  // rank 0's slab
  for (const auto& [k, v] : sol.timings) f.timings[k] = v;
  return f;
}

// report.json of the distributed path: make_report from the pieces' facts; the certificate's worst
// places are PETSc rows (the slabs have no global x); "pieces" names the ranks' files.
nlohmann::json slab_report(const nlohmann::json& scene, const Model& md, const Solution& sol,
                           const SummaryFacts& facts, const SolveOptions& opt, const EngineReport& er, int size) {
  nlohmann::json r = make_report(md, facts, sol, opt, "worst_petsc_row");
  r["engine"] = "petsc";
  r["petsc"] = er.json;
  if (er.json.contains("engine_choice")) r["engine_choice"] = er.json.at("engine_choice");
  std::vector<std::string> vtu, csv;
  for (int q = 0; q < size; ++q) {
    if (scene.at("output").at("vtu").get<bool>()) vtu.push_back(piece_name("solution_rank", q, ".vtu"));
    if (scene.at("output").at("csv").get<bool>()) csv.push_back(piece_name("gamma3_rank", q, ".csv"));
  }
  r["pieces"] = {{"vtu", vtu}, {"gamma3_csv", csv}};
  return r;
}

}  // namespace

std::vector<OutputNamePattern> slab_output_patterns() {
  return {{"solution_rank", ".vtu"}, {"gamma3_rank", ".csv"}};
}

namespace {

// The whole mesh's longest edge (the summary's h; collective).
double longest_edge(const Model& md, MPI_Comm comm) {
  const double h_mine = md.mesh.max_edge_length();
  double h = 0;
  MPI_Allreduce(&h_mine, &h, 1, MPI_DOUBLE, MPI_MAX, comm);
  return h;
}

}  // namespace

void write_slab_results(const std::string& dir, const nlohmann::json& scene, const Model& md, const Piece& slab,
                        const Solution& sol, const SlabResult& out, const SolveOptions& opt, const EngineReport& er,
                        MPI_Comm comm, const std::function<void()>& before_report) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const double h = longest_edge(md, comm);
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
  // The Γ3 rows first (collective): each piece's CSV carries the whole list's index k.
  std::vector<long> index;
  const std::vector<Gamma3Row> mine = owned_rows(md, slab, out.piece);
  const std::vector<Gamma3Row> nodes = gather_rows(mine, md.dim(), index, comm);
  attempt([&] { write_piece(dir, scene, md, slab, out, mine, index, rank); });
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
      if (before_report) before_report();
      const SummaryFacts facts = slab_facts(md, slab, sol, er, h, nodes);
      write_final_report(dir, slab_report(scene, md, sol, facts, opt, er, size));
      std::fputs(summary_table(facts, sol).c_str(), stdout);
      std::printf("results in %s (%d pieces)\n", dir.c_str(), size);
    });
  MPI_Bcast(&code, 1, MPI_INT, 0, comm);
  if (code != 0) throw Error(rank == 0 ? message : "rank 0 could not write the results", static_cast<ExitCode>(code));
}


namespace {

// Every owned node's u, gathered to rank 0 in the whole mesh's numbering (collective): rank 0's
// array of global_nodes × d values, NaN where no rank owned a node; empty on the other ranks.
std::vector<double> gather_whole_u(const Model& md, const Piece& slab, const Vec& u, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int d = md.dim();
  std::vector<long> ids;
  std::vector<double> vals;
  for (Index v = 0; v < md.mesh.num_nodes(); ++v)
    if (slab.owned_node[static_cast<size_t>(v)]) {
      ids.push_back(slab.global_node[static_cast<size_t>(v)]);
      for (int i = 0; i < d; ++i) vals.push_back(u[d * v + i]);
    }
  const int count = static_cast<int>(ids.size());
  std::vector<int> counts(static_cast<size_t>(size)), at(static_cast<size_t>(size), 0), dcounts, dat;
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  for (int q = 1; q < size; ++q) at[static_cast<size_t>(q)] = at[static_cast<size_t>(q - 1)] + counts[static_cast<size_t>(q - 1)];
  for (int q = 0; q < size; ++q) dcounts.push_back(counts[static_cast<size_t>(q)] * d), dat.push_back(at[static_cast<size_t>(q)] * d);
  const size_t total = rank == 0 ? static_cast<size_t>(at.back() + counts.back()) : 0;
  std::vector<long> all_ids(total);
  std::vector<double> all(total * static_cast<size_t>(d));
  MPI_Gatherv(ids.data(), count, MPI_LONG, all_ids.data(), counts.data(), at.data(), MPI_LONG, 0, comm);
  MPI_Gatherv(vals.data(), count * d, MPI_DOUBLE, all.data(), dcounts.data(), dat.data(), MPI_DOUBLE, 0, comm);
  if (rank != 0) return {};
  std::vector<double> whole(static_cast<size_t>(slab.global_nodes) * static_cast<size_t>(d),
                            std::numeric_limits<double>::quiet_NaN());
  for (size_t q = 0; q < total; ++q)
    for (int i = 0; i < d; ++i) whole[static_cast<size_t>(all_ids[q]) * d + i] = all[q * d + i];
  return whole;
}

}  // namespace

void stream_slab_results(const nlohmann::json& scene, const Model& md, const Piece& slab, const Solution& sol,
                         const SlabResult& out, const SolveOptions& opt, const EngineReport& er, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const double h = longest_edge(md, comm);
  std::vector<long> index;
  const std::vector<Gamma3Row> nodes = gather_rows(owned_rows(md, slab, out.piece), md.dim(), index, comm);
  const std::vector<double> whole = gather_whole_u(md, slab, out.piece.u, comm);
  int code = 0;
  if (rank == 0) {
    nlohmann::json report = slab_report(scene, md, sol, slab_facts(md, slab, sol, er, h, nodes), opt, er, size);
    report["files"] = nlohmann::json::array();
    const std::string line = report.dump() + "\n";  // one line: dump() escapes every newline inside
    const size_t bytes = whole.size() * sizeof(double);
    if (std::any_of(whole.begin(), whole.end(), [](double x) { return std::isnan(x); }))
      code = EXIT_INTERNAL;  // a node no rank owned: nothing is sent that could pass for u
    else if (std::fwrite(line.data(), 1, line.size(), stdout) != line.size() ||
             std::fwrite(whole.data(), 1, bytes, stdout) != bytes || std::fflush(stdout) != 0)
      code = EXIT_OUTPUT;
  }
  MPI_Bcast(&code, 1, MPI_INT, 0, comm);
  if (code == EXIT_INTERNAL) throw Error("petsc engine: a node of the whole mesh has no owner's u", EXIT_INTERNAL);
  if (code != 0) throw Error("--stream: the results could not be written to stdout (a closed pipe?)", EXIT_OUTPUT);
}

}  // namespace hemicontact::petsc_engine
