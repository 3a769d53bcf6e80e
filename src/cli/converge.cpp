// hemicontact converge — mesh-convergence study of a scene: the paper's Fig. 3 (Sofonea, Han,
// Barboteu 2017, §5), numerical evidence of the optimal-order estimate of §4.
//
// Sample runs:
//   hemicontact converge problems/sofonea2017-fig2.json --levels 4,8,16,32,64 --reference 128 --out out/conv --plot
//   hemicontact converge problems/sofonea2017-printed.json --levels 4,8,...,128 --reference 256
//
// The problem (P_V^h), eq. (22), is solved on uniform meshes h = 1/L for each level L and on a
// reference mesh h = 1/R (R = 256 in the paper). With P the P1 prolongation onto the reference
// mesh, each level's relative error ‖u_ref − P u_h‖_E/‖u_ref‖_E in the energy norm ‖v‖_E² = a(v,v)
// and the observed order log(e_{i−1}/e_i)/log(h_{i−1}/h_i) (≈ 1 in the paper) are written to
// DIR/convergence.csv and DIR/convergence.json and printed; --plot draws DIR/convergence.png
// (scripts/plot_convergence.py). Exit code 3 (4) when a solve did not converge (certify).
#include "cli.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/study_writers.hpp>
#include <hemicontact/output/vtk_writer.hpp>
#include <hemicontact/config.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/engine_choice.hpp>
#include <hemicontact/studies/adapt_study.hpp>
#include <hemicontact/studies/convergence.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace hemicontact::cli {

namespace {

// `converge --adaptive`: the work-precision study of studies/adapt_study.hpp (uniform, graded, adaptive
// against one reference), written to DIR/work_precision.{csv,json} and drawn to work_precision.png.
int converge_adaptive(const std::vector<std::string>& args) {
  SceneArgs a = parse_scene_args(args, {"--levels", "--reference", "--graded-levels", "--graded-power"});
  const std::string name = std::filesystem::path(a.scene).stem().string();
  if (std::find(args.begin(), args.end(), "--out") == args.end()) a.out = "out/" + name + "-adaptive";
  WorkPrecisionRequest req;
  std::string uniform_text = ADAPTIVE_LEVELS, graded_text = ADAPTIVE_LEVELS;
  for (const auto& [key, value] : a.extra) {
    if (key == "--levels") uniform_text = value;
    if (key == "--graded-levels") graded_text = value;
    if (key == "--reference") req.reference = value;
    if (key == "--graded-power") {
      char* end = nullptr;
      req.graded_power = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0') throw UsageError("--graded-power: expected a number, got '" + value + "'");
      // The bound of the key it sets (inf, or 50, failed later naming a degenerate cell).
      check_key_range("mesh.grading.power", req.graded_power, "--graded-power", EXIT_USAGE);
    }
  }
  req.uniform_levels = uniform_text == "none" ? std::vector<int>{} : parse_levels(uniform_text);
  req.graded_levels = graded_text == "none" ? std::vector<int>{} : parse_levels(graded_text);
  if (a.quiet) set_log_level(LogLevel::WARN);
  require_utf8_scene_name(a.scene, "work_precision.json");
  const nlohmann::json scene = load_scene(a.scene, a.overrides);
  req.adapt = adapt_options_from_scene(scene);  // target_error null: the default 0.01
  const OutputLock lock = prepare_output_dir(a.out, a.force, {"work_precision.csv", "work_precision.json", "work_precision.png"});
  const std::filesystem::path out(a.out);
  const WorkPrecisionStudy st = run_work_precision(scene, scene_directory(a.scene), req);
  write_text_file((out / "work_precision.csv").string(), work_precision_csv(st));
  nlohmann::json js = work_precision_json(st);
  js["name"] = name;
  js["scene_file"] = a.scene;
  js["target_error"] = req.adapt.target_error;
  write_text_file((out / "work_precision.json").string(), js.dump(2) + '\n');
  std::printf("%s: work-precision study against the reference %s (%lld dofs, its estimate %.3g)\n", name.c_str(),
              st.reference.c_str(), static_cast<long long>(st.reference_dofs), st.reference_estimate);
  std::printf("%-9s %6s %9s %9s %11s %11s %11s %10s %10s %s\n", "family", "level", "dofs", "seconds", "error",
              "corrected", "estimate", "eff.index", "cert.", "ok");
  for (const StudyPoint& p : st.points)
    std::printf("%-9s %6d %9lld %9.3g %11.4g %11.4g %11.4g %10.3g %10.2e %s\n", p.family.c_str(), p.level,
                static_cast<long long>(p.dofs), p.seconds, p.error, p.error_corrected, p.estimate, p.efficiency,
                p.certificate,
                p.ok ? "yes" : "NO");
  for (const char* f : {"uniform", "graded", "adaptive"})
    if (std::isfinite(st.slope(f))) std::printf("%s: error ~ N^%.3f (last 4 meshes)\n", f, st.slope(f));
  std::printf("results in %s\n", a.out.c_str());
  if ((a.plot || scene.at("output").at("plot").get<bool>()) &&
      run_plot_script("plot_work_precision.py",
                      {(out / "work_precision.csv").string(), "--out", (out / "work_precision.png").string(), "--title",
                       name},
                      (out / "work_precision.png").string()) != 0) {
    std::fprintf(stderr, "hemicontact: converge: --plot: %s was not drawn (the CSV and JSON are written)\n",
                 (out / "work_precision.png").c_str());
    return EXIT_INPUT;
  }
  if (std::filesystem::exists(out / "work_precision.png")) record_output_file((out / "work_precision.png").string());
  return st.ok() ? EXIT_OK : EXIT_CERTIFICATE;
}

}  // namespace

int cmd_converge(const std::vector<std::string>& all_args) {
  refuse_mpi_ranks("converge");
  std::vector<std::string> args;
  bool adaptive = false;
  for (size_t i = 0; i < all_args.size(); ++i) {
    if (all_args[i] == "--adaptive") adaptive = true;
    else args.push_back(all_args[i]);
    if (all_args[i] == "--set" && i + 1 < all_args.size()) args.push_back(all_args[++i]);  // a value, never a flag
  }
  if (adaptive) return converge_adaptive(args);
  SceneArgs a = parse_scene_args(args, {"--levels", "--reference"});
  const std::string name = std::filesystem::path(a.scene).stem().string();
  if (std::find(args.begin(), args.end(), "--out") == args.end()) a.out = "out/" + name + "-convergence";
  std::string levels_text = CONVERGE_LEVELS, reference_text = CONVERGE_REFERENCE;  // the paper's study
  for (const auto& [key, value] : a.extra) (key == "--levels" ? levels_text : reference_text) = value;
  const std::vector<int> levels = parse_levels(levels_text);
  std::vector<int> reference;
  try {
    reference = parse_levels(reference_text);
  } catch (const Error&) {
  }
  if (reference.size() != 1 || reference_text.find(',') != std::string::npos)
    throw UsageError("--reference: expected one positive integer up to " + std::to_string(MAX_LEVEL) +
                     " (2^20 cells per side, the level cap), got '" + reference_text + "'");
  if (a.quiet) set_log_level(LogLevel::WARN);

  require_utf8_scene_name(a.scene, "convergence.json");
  const nlohmann::json scene = load_scene(a.scene, a.overrides);
  // The engine `solve` would take for the largest mesh, the reference's (each level is chosen for alike).
  const EngineChoice engine = convergence_engine(scene, scene_directory(a.scene), reference[0], petsc_engine_available());
  log_engine_choice(engine);
  // level_<n>.vtu: one per solved level (the reference's too), checked with the fixed names.
  const OutputLock lock = prepare_output_dir(
      a.out, a.force, {"convergence.csv", "convergence.json", "convergence.png", "convergence.pvd"}, {{"level_", ".vtu"}});
  const std::filesystem::path out(a.out);

  // One VTU per solved level as it completes, and a .pvd that steps through them in ParaView.
  const VtuFormat vtu_format =
      scene.at("output").at("vtu_format").get<std::string>() == "ascii" ? VtuFormat::ASCII : VtuFormat::BINARY;
  std::vector<std::pair<double, std::string>> vtus;
  const bool write_vtus = scene.at("output").at("vtu").get<bool>();
  // Each finished level is kept as it completes, so an interrupt loses none of them: its VTU, and
  // convergence.csv with the levels so far (rewritten whole, atomically). convergence.json, written
  // last, marks the study complete; an interrupt names what was kept.
  const auto on_level = [&](const ConvergenceStudy& so_far, int n, const Model& md, const Solution& sol) {
    if (write_vtus) {
      const std::string file = "level_" + std::to_string(n) + ".vtu";
      write_vtu((out / file).string(), md, sol, vtu_format);
      vtus.emplace_back(n, file);
    }
    if (!so_far.levels.empty()) write_convergence_csv((out / "convergence.csv").string(), so_far);
  };
  const ConvergenceStudy st =
      run_convergence(scene, scene_directory(a.scene), levels, reference[0], on_level, petsc_engine_available());
  if (write_vtus) {
    std::sort(vtus.begin(), vtus.end());
    write_pvd((out / "convergence.pvd").string(), vtus);
  }

  nlohmann::json js = convergence_json(st);
  js["name"] = name;
  js["scene_file"] = a.scene;
  js["engine_choice"] = engine_choice_json(engine);
  write_convergence_csv((out / "convergence.csv").string(), st);
  write_text_file((out / "convergence.json").string(), js.dump(2) + '\n');
  std::printf("%s: convergence against the reference n = %d\n", name.c_str(), reference[0]);
  std::fputs(convergence_table(st).c_str(), stdout);
  std::printf("results in %s\n", a.out.c_str());

  const bool plot_failed =
      (a.plot || scene.at("output").at("plot").get<bool>()) &&
      run_plot_script("plot_convergence.py",
                      {(out / "convergence.csv").string(), "--out", (out / "convergence.png").string(), "--title", name},
                      (out / "convergence.png").string()) != 0;
  if (std::filesystem::exists(out / "convergence.png")) record_output_file((out / "convergence.png").string());
  if (!st.ok()) {
    std::string not_converged, not_certified;
    std::vector<ConvergenceLevel> all = st.levels;
    if (std::none_of(all.begin(), all.end(), [&](const ConvergenceLevel& l) { return l.n == st.reference.n; }))
      all.push_back(st.reference);
    for (const auto& l : all) {
      std::string& list = !l.converged ? not_converged : not_certified;
      if (!l.ok) list += (list.empty() ? "n = " : ", ") + std::to_string(l.n);
    }
    if (!not_converged.empty())
      std::fprintf(stderr, "hemicontact: converge: not converged at %s\n", not_converged.c_str());
    if (!not_certified.empty())
      std::fprintf(stderr, "hemicontact: converge: certificate failed at %s\n", not_certified.c_str());
    return not_converged.empty() ? EXIT_CERTIFICATE : EXIT_NOT_CONVERGED;
  }
  if (plot_failed) {
    std::fprintf(stderr, "hemicontact: converge: --plot: %s was not drawn (the CSV and JSON are written)\n",
                 (out / "convergence.png").c_str());
    return EXIT_INPUT;
  }
  return EXIT_OK;
}

}  // namespace hemicontact::cli
