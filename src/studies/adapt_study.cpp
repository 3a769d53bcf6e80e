#include <hemicontact/studies/adapt_study.hpp>

#include <hemicontact/solver/engine_choice.hpp>
#include <hemicontact/studies/petsc_process.hpp>

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/fem/prolongation.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>
#include <hemicontact/studies/convergence.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace hemicontact {
namespace {
using json = nlohmann::json;

json with_mesh(json scene, int n) {
  scene["mesh"]["n"] = n;
  scene["mesh"]["nx"] = n;
  scene["mesh"]["ny"] = n;
  if (scene["mesh"].contains("nz")) scene["mesh"]["nz"] = n;
  return scene;
}

struct Kept {
  Mesh mesh;
  Vec u;
  StudyPoint p;
  double estimate_abs = 0;
};

}  // namespace

double WorkPrecisionStudy::slope(const std::string& family, int last) const {
  std::vector<double> x, y;
  for (const StudyPoint& p : points)
    if (p.family == family && p.error_corrected > 0) {
      x.push_back(std::log(static_cast<double>(p.dofs)));
      y.push_back(std::log(p.error_corrected));
    }
  if (x.size() < 2) return std::nan("");
  const size_t n = std::min(x.size(), static_cast<size_t>(std::max(2, last))), s0 = x.size() - n;
  double mx = 0, my = 0;
  for (size_t i = s0; i < x.size(); ++i) mx += x[i] / n, my += y[i] / n;
  double sxy = 0, sxx = 0;
  for (size_t i = s0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
  return sxy / sxx;
}

bool WorkPrecisionStudy::ok() const {
  for (const StudyPoint& p : points)
    if (!p.ok) return false;
  return true;
}

namespace {

// --reference uniform:R or adaptive:T.
struct ReferenceSpec {
  std::string kind;
  double value = 0;
};

ReferenceSpec parse_reference(const std::string& reference) {
  const auto colon = reference.find(':');
  ReferenceSpec r;
  r.kind = reference.substr(0, colon);
  const std::string& kind = r.kind;
  double& value = r.value;
  if (colon != std::string::npos) {
    std::istringstream in(reference.substr(colon + 1));
    in >> value;
    if (!in || !in.eof()) value = 0;
  }
  if ((kind != "uniform" && kind != "adaptive") || !(value > 0) ||
      (kind == "uniform" && value != std::floor(value)) || (kind == "adaptive" && value >= 1))
    input_error("--reference: expected uniform:R (R cells per side) or adaptive:T (0 < T < 1), got '" + reference +
                "'");
  // T is a target_error of the same adaptive sequence: the key's floor holds (1e-9 was accepted).
  if (kind == "adaptive") check_key_range("adapt.target_error", value, "--reference adaptive:T", EXIT_INPUT);
  if (kind == "uniform" && value > MAX_LEVEL)
    input_error("--reference uniform:R: R = " + reference.substr(colon + 1) + " is above the level cap " +
                std::to_string(MAX_LEVEL) + " (2^20 cells per side)");
  return r;
}

// The error of a solution against the reference: relative energy norm, corrected by the
// reference's own estimate.
struct ReferenceError {
  const Model& ref;
  const Solution& sref;
  double reference_estimate;
  double norm_ref;
  void measure(const Mesh& mesh, const Vec& u, StudyPoint& p) const {
    // The interpolant vanishes on the reference's Γ1 (every mesh clamps the same sides), so a(e, e)
    // through the model's K_x is the energy norm of the difference.
    const Vec e = sref.u - prolongate(mesh, u, ref.mesh);
    p.error = std::sqrt(std::max(0.0, ref.a(e, e))) / norm_ref;
    p.error_corrected = std::hypot(p.error, reference_estimate);
    p.efficiency = p.estimate / p.error_corrected;
  }
};

// A structured family (uniform or graded meshes), one solve per level, measured against the reference.
void structured_family(const json& scene, const std::string& scene_dir, const SolveOptions& opt,
                       const WorkPrecisionRequest& req, const ReferenceError& err, const std::string& family,
                       const std::vector<int>& levels, bool graded, WorkPrecisionStudy& st) {
  for (int n : levels) {
    json s = with_mesh(scene, n);
    if (graded) {
      s["mesh"]["grading"]["x"] = req.graded_x;
      s["mesh"]["grading"]["y"] = req.graded_y;
      s["mesh"]["grading"]["power"] = req.graded_power;
    }
    const auto t0 = clk::now();
    const Model md = build_model(s, scene_dir);
    const Solution sol = solve(md, opt);
    StudyPoint p;
    p.seconds = since(t0);
    p.family = family;
    p.level = n;
    p.dofs = md.dofs.n_free();
    const ErrorEstimate e = estimate_error(md, sol, req.adapt.estimator);
    p.estimate = e.relative;
    p.certificate = sol.certificate.max_residual;
    p.ok = sol.ok();
    err.measure(md.mesh, sol.u, p);
    log_info() << family << " n = " << n << ": " << p.dofs << " dofs, error " << p.error << ", " << p.seconds << " s";
    st.points.push_back(p);
  }
}

// An adaptive level as the study keeps it: its mesh, solution and point.
Kept kept_level(const AdaptLevel& L, const Model& md, const Solution& sol, const ErrorEstimate& e) {
  Kept k;
  k.mesh = md.mesh;
  k.u = sol.u;
  k.p.family = "adaptive";
  k.p.level = L.level;
  k.p.dofs = L.dofs;
  k.p.seconds = L.cumulative_seconds;
  k.p.estimate = L.estimate;
  k.p.certificate = L.certificate;
  k.p.ok = L.ok;
  k.estimate_abs = e.total;
  return k;
}

}  // namespace

WorkPrecisionStudy run_work_precision(const json& scene, const std::string& scene_dir, const WorkPrecisionRequest& req) {
  const std::string type = scene.at("mesh").at("type").get<std::string>();
  if (type != "rectangle" && type != "box")
    input_error("converge --adaptive: the scene's mesh must be a generated rectangle or box (mesh.type = rectangle "
                "or box)");
  SolveOptions opt = solve_options_from_scene(scene);
  opt.smallness = false;  // a diagnostic, not part of the work measured
  WorkPrecisionStudy st;
  st.reference = req.reference;
  const ReferenceSpec spec = parse_reference(req.reference);
  const std::string& kind = spec.kind;
  const double value = spec.value;

  // The adaptive sequence, kept level by level (its meshes and solutions).
  std::vector<Kept> adaptive;
  const auto keep = [&](const AdaptLevel& L, const Model& md, const Solution& sol, const ErrorEstimate& e) {
    adaptive.push_back(kept_level(L, md, sol, e));
  };

  Model ref;
  Solution sref;
  if (kind == "uniform") {
    const nlohmann::json uniform = with_mesh(scene, static_cast<int>(value));
    ref = build_model(uniform, scene_dir);
    sref = scene_engine(uniform, scene_dir, petsc_engine_available(), "adapt study: the uniform reference")(ref, opt);
    st.reference_estimate = estimate_error(ref, sref, req.adapt.estimator).relative;
    run_adaptive(scene, build_mesh(scene, scene_dir), req.adapt, opt, keep, petsc_level_engine(scene, scene_dir));
  } else {
    AdaptOptions deeper = req.adapt;
    deeper.target_error = value;
    AdaptResult r =
        run_adaptive(scene, build_mesh(scene, scene_dir), deeper, opt, keep, petsc_level_engine(scene, scene_dir));
    ref = std::move(r.model);
    sref = std::move(r.solution);
    st.reference_estimate = r.history.back().estimate;
    adaptive.pop_back();  // the reference itself
    // The study's sequence stops where its own target would have stopped it.
    for (size_t i = 0; i < adaptive.size(); ++i)
      if (adaptive[i].p.estimate <= req.adapt.target_error) {
        adaptive.resize(i + 1);
        break;
      }
  }
  if (!sref.ok()) log_warn() << "converge --adaptive: the reference solve was not certified: " << sref.message;
  st.reference_dofs = ref.dofs.n_free();
  const ReferenceError err{ref, sref, st.reference_estimate, std::sqrt(std::max(0.0, ref.a(sref.u, sref.u)))};
  structured_family(scene, scene_dir, opt, req, err, "uniform", req.uniform_levels, false, st);
  // mesh.grading grades rectangles only: a box has no graded family.
  if (type == "rectangle") structured_family(scene, scene_dir, opt, req, err, "graded", req.graded_levels, true, st);
  else if (!req.graded_levels.empty()) log_info() << "converge --adaptive: no graded family for a box (mesh.grading grades rectangles)";
  for (Kept& k : adaptive) {
    err.measure(k.mesh, k.u, k.p);
    st.points.push_back(k.p);
  }
  return st;
}

std::string work_precision_csv(const WorkPrecisionStudy& st) {
  std::string s = "family,level,dofs,seconds,error,error_corrected,estimate,efficiency,certificate,ok\n";
  char buf[256];
  for (const StudyPoint& p : st.points) {
    std::snprintf(buf, sizeof buf, "%s,%d,%lld,%.6g,%.9g,%.9g,%.9g,%.6g,%.3e,%d\n", p.family.c_str(), p.level,
                  static_cast<long long>(p.dofs), p.seconds, p.error, p.error_corrected, p.estimate, p.efficiency,
                  p.certificate,
                  p.ok ? 1 : 0);
    s += buf;
  }
  return s;
}

json work_precision_json(const WorkPrecisionStudy& st) {
  json j;
  j["reference"] = st.reference;
  j["reference_dofs"] = st.reference_dofs;
  j["reference_estimate"] = st.reference_estimate;
  json pts = json::array();
  for (const StudyPoint& p : st.points)
    pts.push_back({{"family", p.family},
                   {"level", p.level},
                   {"dofs", p.dofs},
                   {"seconds", p.seconds},
                   {"error", p.error},
                   {"error_corrected", p.error_corrected},
                   {"estimate", p.estimate},
                   {"efficiency", std::isfinite(p.efficiency) ? json(p.efficiency) : json(nullptr)},
                   {"certificate", p.certificate},
                   {"ok", p.ok}});
  j["points"] = pts;
  json slopes;
  for (const char* f : {"uniform", "graded", "adaptive"}) {
    const double s = st.slope(f);
    slopes[f] = std::isfinite(s) ? json(s) : json(nullptr);
  }
  j["slopes_last4"] = slopes;
  j["ok"] = st.ok();
  return j;
}

}  // namespace hemicontact
