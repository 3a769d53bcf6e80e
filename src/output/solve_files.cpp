#include <hemicontact/output/solve_files.hpp>

#include <hemicontact/output/csv_writer.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/output/vtk_writer.hpp>

#include <cstdio>
#include <filesystem>

namespace hemicontact {

std::vector<std::string> solve_output_names() {
  return {"report.json", "solution.vtu", "gamma3.csv", "fig2.png", "status3d.png", ADAPT_LEVELS_FILE};
}

void write_solution_files(const std::string& dir, const nlohmann::json& scene, const Model& md, const Solution& sol,
                          const Vec* cell_indicators) {
  const std::filesystem::path out(dir);
  const VtuFormat vtu_format =
      scene.at("output").at("vtu_format").get<std::string>() == "ascii" ? VtuFormat::ASCII : VtuFormat::BINARY;
  if (scene.at("output").at("vtu").get<bool>())
    write_vtu((out / "solution.vtu").string(), md, sol, vtu_format, cell_indicators);
  if (scene.at("output").at("csv").get<bool>()) write_gamma3_csv((out / "gamma3.csv").string(), md, sol);
}

nlohmann::json solve_report(const Model& md, const Solution& sol, const SolveOptions& opt, const nlohmann::json& extra) {
  nlohmann::json report = make_report(md, sol, opt);
  for (const auto& [key, value] : extra.items()) report[key] = value;
  return report;
}

void write_final_report(const std::string& dir, nlohmann::json report) {
  // The files there now: a picture is listed before it is drawn (cli/plot.cpp), and one that was
  // not drawn is not among the results.
  report["files"] = nlohmann::json::array();
  for (const std::string& f : output_files(dir)) {
    std::error_code ec;
    if (f != "report.json" && std::filesystem::is_regular_file(std::filesystem::path(dir) / f, ec))
      report["files"].push_back(f);
  }
  report["files"].push_back("report.json");
  write_report((std::filesystem::path(dir) / "report.json").string(), report);
}

}  // namespace hemicontact
