#include <hemicontact/scene/build_model.hpp>

#include <hemicontact/contact/law_factory.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/material/material_factory.hpp>
#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/mesh/generators.hpp>
#include <hemicontact/mesh/gmsh_import.hpp>
#include <hemicontact/scene/config.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>

namespace hemicontact {
namespace {

using json = nlohmann::json;
using clk = std::chrono::steady_clock;
double since(clk::time_point t0) { return std::chrono::duration<double>(clk::now() - t0).count(); }

double number_or(const json& v, double fallback) { return v.is_null() ? fallback : v.get<double>(); }

std::vector<BoundarySelector> selectors(const json& list, const std::string& name, double scale) {
  std::vector<BoundarySelector> out;
  for (size_t i = 0; i < list.size(); ++i) {
    const json& s = list[i];
    BoundarySelector b;
    b.context = "boundary." + name + "[" + std::to_string(i) + "]";
    if (!s["side"].is_null()) b.side = s["side"].get<std::string>();
    if (!s["physical"].is_null()) b.physical = s["physical"].get<std::string>();
    b.from = number_or(s["from"], -INF);
    b.to = number_or(s["to"], INF);
    if (s.contains("components"))
      for (const auto& c : s["components"])
        b.components.push_back(static_cast<int>(std::string("xyz").find(c.get<std::string>())));
    if (s.contains("traction")) {
      const auto t = s["traction"].get<std::vector<double>>();
      b.traction = scale * Eigen::Map<const Vec>(t.data(), static_cast<Index>(t.size()));
    }
    out.push_back(std::move(b));
  }
  return out;
}

Gap make_gap(const json& g) {
  Gap gap;
  if (g.is_null() || (g.is_string() && g.get<std::string>() == "inf")) return gap;
  if (g.is_number()) {
    gap.constant = g.get<double>();
    if (!(gap.constant >= 0)) input_error("contact.gap: negative thickness g = " + std::to_string(gap.constant));
    return gap;
  }
  const std::string along = g.at("along").get<std::string>();
  gap.axis = along == "x" ? 0 : along == "y" ? 1 : 2;
  for (const auto& p : g.at("points")) {
    if (p.size() != 2) input_error("contact.gap.points: each point is [coordinate, g]");
    gap.points.emplace_back(p[0].get<double>(), p[1].get<double>());
  }
  if (gap.points.empty()) input_error("contact.gap.points: empty table");
  for (size_t i = 0; i < gap.points.size(); ++i) {
    if (!(gap.points[i].second >= 0))
      input_error("contact.gap.points[" + std::to_string(i) +
                  "]: negative thickness g = " + std::to_string(gap.points[i].second));
    if (i > 0 && !(gap.points[i].first > gap.points[i - 1].first))
      input_error("contact.gap.points[" + std::to_string(i) + "]: coordinates must increase");
  }
  return gap;
}

}  // namespace

Mesh build_mesh(const json& scene, const std::string& scene_dir) {
  const json& m = scene.at("mesh");
  Mesh mesh;
  auto t0 = clk::now();
  if (m.at("type") == "gmsh") {
    if (m.at("file").is_null()) input_error("mesh.file: required when mesh.type is 'gmsh'");
    std::filesystem::path p = m.at("file").get<std::string>();
    if (p.is_relative()) p = std::filesystem::path(scene_dir) / p;
    mesh = read_gmsh(p.string());
  } else if (m.at("type") == "box") {
    BoxSpec s;
    const auto x = m.at("x").get<std::vector<double>>(), y = m.at("y").get<std::vector<double>>(),
               z = m.at("z").get<std::vector<double>>();
    if (x.size() != 2 || y.size() != 2 || z.size() != 2)
      input_error("mesh.x, mesh.y, mesh.z: each is an interval [a, b]");
    s.x0 = x[0];
    s.x1 = x[1];
    s.y0 = y[0];
    s.y1 = y[1];
    s.z0 = z[0];
    s.z1 = z[1];
    // validate_scene copies n into nx, ny and nz.
    s.nx = m.at("nx").get<int>();
    s.ny = m.at("ny").get<int>();
    s.nz = m.at("nz").get<int>();
    s.pattern = parse_box_pattern(m.at("pattern").get<std::string>());
    s.perturb = m.at("perturb").get<double>();
    s.seed = m.at("seed").get<unsigned>();
    mesh = make_box(s);
  } else {
    RectangleSpec s;
    const auto x = m.at("x").get<std::vector<double>>(), y = m.at("y").get<std::vector<double>>();
    if (x.size() != 2 || y.size() != 2) input_error("mesh.x, mesh.y: each is an interval [a, b]");
    s.x0 = x[0];
    s.x1 = x[1];
    s.y0 = y[0];
    s.y1 = y[1];
    s.nx = m.at("n").is_null() ? m.at("nx").get<int>() : m.at("n").get<int>();
    s.ny = m.at("n").is_null() ? m.at("ny").get<int>() : m.at("n").get<int>();
    s.diagonal = parse_diagonal(m.at("diagonal").get<std::string>());
    s.perturb = m.at("perturb").get<double>();
    s.seed = m.at("seed").get<unsigned>();
    mesh = make_rectangle(s);
  }
  log_debug() << "mesh: " << mesh.origin << " (" << since(t0) << " s)";
  assign_scene_boundary(mesh, scene);
  return mesh;
}

void assign_scene_boundary(Mesh& mesh, const json& scene) {
  check_cells(mesh);
  const double scale = scene.at("loads").at("scale").get<double>();
  BoundarySpec spec;
  spec.gamma1 = selectors(scene.at("boundary").at("gamma1"), "gamma1", scale);
  spec.gamma2 = selectors(scene.at("boundary").at("gamma2"), "gamma2", scale);
  spec.gamma3 = selectors(scene.at("boundary").at("gamma3"), "gamma3", scale);
  spec.rollers = selectors(scene.at("boundary").at("rollers"), "rollers", scale);
  assign_boundary(mesh, spec);
}

Model build_model(const json& scene, const std::string& scene_dir) {
  auto t0 = clk::now();
  Mesh mesh = build_mesh(scene, scene_dir);
  const double t_mesh = since(t0);
  Model md = build_model(scene, std::move(mesh));
  md.timings["mesh"] = t_mesh;
  return md;
}

Model build_model(const json& scene, Mesh mesh) {
  Model md;
  md.scene = scene;
  md.mesh = std::move(mesh);
  const int d = md.mesh.dim;

  md.material = make_material(scene.at("material"), d);

  md.gap = make_gap(scene.at("contact").at("gap"));
  md.normal_law = make_normal_law(scene.at("contact").at("normal_law"));
  md.friction = make_friction_bound(scene.at("contact").at("friction"), md.normal_law);

  md.clamped = clamped_nodes(md.mesh);
  md.contact = make_contact_nodes(md.mesh, md.clamped, md.gap);
  const bool has_contact_law = md.normal_law || md.friction || !md.gap.is_infinite();
  if (md.contact.size() == 0 && has_contact_law)
    input_error("boundary.gamma3: the scene defines a contact law but Γ3 has no free node");
  md.dofs = DofMap(md.mesh, md.clamped, md.contact);

  const auto t0 = clk::now();
  // A nonlinear law's K is its tangent at u = 0 (the small-strain stiffness): it sets the solver's
  // scales and the K(0) energy norm; equilibrium and energies use internal_force / elastic_energy.
  md.K = md.material->is_linear() ? assemble_stiffness(md.mesh, *md.material)
                                  : assemble_stiffness(md.mesh, md.material->tangent(Vec::Zero(voigt_size(d))));
  const auto f0v = scene.at("loads").at("body_force").get<std::vector<double>>();
  if (static_cast<int>(f0v.size()) != d) input_error("loads.body_force: expected " + std::to_string(d) + " components");
  const Vec f0 = scene.at("loads").at("scale").get<double>() * Eigen::Map<const Vec>(f0v.data(), d);
  md.f = assemble_body_force(md.mesh, f0) + assemble_tractions(md.mesh);
  md.Kx = md.dofs.reduce(md.K);
  md.fx = md.dofs.to_reduced(md.f);
  md.timings["assembly"] = since(t0);
  log_info() << "model: " << md.mesh.origin << ", " << md.mesh.num_nodes() << " nodes, " << md.mesh.num_cells()
             << " cells, " << md.dofs.n_free() << " dofs, " << md.contact.size() << " Γ3 nodes ("
             << md.timings["assembly"] << " s assembly)";
  return md;
}

SolveOptions solve_options_from_scene(const nlohmann::json& scene) {
  const auto& s = scene.at("solver");
  SolveOptions o;
  o.backend = s.at("backend").get<std::string>();
  o.formulation = s.at("formulation").get<std::string>();
  o.polish = s.at("polish").get<bool>();
  o.backend_options.tol = s.at("tol").get<double>();
  o.backend_options.max_iter = s.at("max_iter").get<int>();
  o.backend_options.print_level = s.at("print_level").get<int>();
  for (const auto& [k, v] : s.at("options").items())
    o.backend_options.extra[k] = v.is_string() ? v.get<std::string>() : v.dump();
  o.eps_tau = s.at("eps_tau").get<double>();
  o.eps_nu = s.at("eps_nu").get<double>();
  o.eps_start = s.at("continuation").at("eps_start").get<double>();
  o.eps_factor = s.at("continuation").at("factor").get<double>();
  o.tol_u = s.at("fixed_point").at("tol_u").get<double>();
  o.max_outer = s.at("fixed_point").at("max_iters").get<int>();
  o.relaxation = s.at("fixed_point").at("relaxation").get<double>();
  o.allow_not_converged = s.at("fixed_point").at("allow_not_converged").get<bool>();
  o.contraction_floor = s.at("fixed_point").at("contraction_floor").get<double>();
  o.stall_ratio = s.at("fixed_point").at("stall_ratio").get<double>();
  o.stall_iters = s.at("fixed_point").at("stall_iters").get<int>();
  o.certificate_tol = scene.at("check").at("certificate_tol").get<double>();
  o.status_tol = scene.at("check").at("status_tol").get<double>();
  o.smallness = scene.at("check").at("smallness").get<bool>();
  o.smallness_method = scene.at("check").at("smallness_method").get<std::string>();
  return o;
}

}  // namespace hemicontact
