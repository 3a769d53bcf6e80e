#pragma once
/// @file solve_files.hpp  The result files of one solve, as `hemicontact solve` writes them into its
/// output folder (output_dir.hpp), for the CLI and for hosts that write the same set (the Python
/// module's Result.write): solution.vtu and gamma3.csv as the scene's output block asks,
/// adapt_levels.json for an adaptive solve (solver/adapt.hpp: adapt_levels_json), and report.json last, listing every file of the set.
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace hemicontact {

/// An adaptive solve's certified levels so far, rewritten after each level (kept when the run is
/// interrupted or fails; report.json, written last, marks a finished run).
inline constexpr const char* ADAPT_LEVELS_FILE = "adapt_levels.json";

/// @return the files a solve may write into its folder (prepare_output_dir's will_write).
std::vector<std::string> solve_output_names();

/// @brief Write solution.vtu (output.vtu, in output.vtu_format) and gamma3.csv (output.csv) into
/// the prepared folder @p dir; @p cell_indicators (adaptive runs) become the VTU's error_indicator.
/// @throws Error (EXIT_OUTPUT) if a file cannot be written
void write_solution_files(const std::string& dir, const nlohmann::json& scene, const Model& md, const Solution& sol,
                          const Vec* cell_indicators = nullptr);

/// @brief make_report() with the keys of @p extra added (a later key wins).
nlohmann::json solve_report(const Model& md, const Solution& sol, const SolveOptions& opt, const nlohmann::json& extra);

/// @brief Write @p report as @p dir/report.json, its "files" the folder's manifest (every file of
/// the set written so far) and report.json itself; written last, it marks the set complete.
/// @throws Error (EXIT_OUTPUT) if it cannot be written
void write_final_report(const std::string& dir, nlohmann::json report);

}  // namespace hemicontact
