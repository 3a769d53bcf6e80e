#pragma once
/// @file study_writers.hpp  Tables, JSON and CSV of the studies: the mesh-convergence study
/// (`hemicontact converge`, studies/convergence.hpp) and the search for distinct solutions
/// (`hemicontact minima`, studies/minima.hpp). They read the studies' records in problem/
/// (convergence_study.hpp, minima_report.hpp), not the studies' code.

#include <hemicontact/problem/convergence_study.hpp>
#include <hemicontact/problem/minima_report.hpp>
#include <hemicontact/problem/model.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace hemicontact {

/// @brief The study as JSON: {"reference": level, "levels": [level...], "backend", "ok", "failed",
/// "scene", "rate_fit": {alpha, C, levels_used, max_rel_residual} or null} with each level {n, h, h_max, dofs,
/// energy_norm, error, order, seconds, status_counts, certificate_max_residual, converged, certified, ok, nested,
/// message}; NaN orders are null.
/// @param study the study @return the JSON object
nlohmann::json convergence_json(const ConvergenceStudy& study);

/// @brief Write one CSV row per level (the reference is not a row), header
/// @code
///   n,h,h_max,dofs,energy_norm,error,order,seconds,separated,compliance,contact,stick,slip+,slip-,slip,certificate_max_residual,converged,certified,ok
/// @endcode
/// Numbers are written in full precision; the first level's order is empty; booleans are 0/1.
/// @param path the file to write (its directory must exist) @param study the study
/// @throws Error (EXIT_OUTPUT) if the file cannot be written
void write_convergence_csv(const std::string& path, const ConvergenceStudy& study);

/// @brief A fixed-width table for stdout: one line per level, then the reference and a verdict.
/// @param study the study @return several lines, each ending in '\n'
std::string convergence_table(const ConvergenceStudy& study);

/// The report as JSON (minima.json): options, smallness, runs, and per distinct solution its
/// energies, status counts, certificate, second-order check, starts, backends and Γ3 nodes
/// (x, y, u_nu, u_tau, sigma_nu, sigma_tau, xi, lambda, status).
/// @param md the model @param r the report @return the JSON object
nlohmann::json minima_json(const Model& md, const MinimaReport& r);

/// One CSV row per distinct solution (minima.csv): k, energy, energy_norm, type, lambda_min,
/// certificate, n_starts, backends, starts, then the status counts.
/// @param path the file @param r the report @throws Error (EXIT_OUTPUT) if it cannot be written
void write_minima_csv(const std::string& path, const MinimaReport& r);

/// One CSV row per finished run (minima-runs.csv), in run order: run, start, backend, converged,
/// certified, energy, certificate, seconds, message. Rewritten as each run ends, so an interrupted
/// search keeps the runs it finished (MinimaOptions::on_run).
/// @param path the file @param runs the runs so far @throws Error (EXIT_OUTPUT) if it cannot be written
void write_minima_runs_csv(const std::string& path, const std::vector<MinimaRun>& runs);

/// The table printed by `hemicontact minima`: one line per distinct solution, then the runs
/// that were not certified. @param r the report @return lines ending in '\n'
std::string minima_table(const MinimaReport& r);

}  // namespace hemicontact
