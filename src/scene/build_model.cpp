#include <hemicontact/scene/build_model.hpp>

#include <hemicontact/contact/law_factory.hpp>
#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/core/process.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/material/material_factory.hpp>
#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/mesh/generators.hpp>
#include <hemicontact/mesh/gmsh_import.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/scene/slab_mesh.hpp>
#include <hemicontact/mesh/slabs.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <sys/resource.h>

namespace hemicontact {
namespace {
using json = nlohmann::json;

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

// First number in a file (a cgroup's memory.max holds "max" when unlimited): -1 if none.
double read_number(const std::string& path) {
  std::ifstream in(path);
  double v = -1;
  if (!(in >> v)) return -1;
  return v;
}

// A "Key:   N kB" line of /proc/meminfo or /proc/self/status, in bytes (-1 if absent).
double proc_kb(const char* file, const std::string& key) {
  std::ifstream in(file);
  for (std::string k; in >> k;) {
    if (k == key) {
      double kb = -1;
      in >> kb;
      return kb * 1024.0;
    }
    in.ignore(1 << 10, '\n');
  }
  return -1;
}

// OpenBLAS maps a work buffer (OPENBLAS_BUFFER_BYTES) per thread: its worker threads' when the
// library is loaded (they are in VmSize already), the calling thread's at its first BLAS call. Under
// ulimit -v a buffer that does not fit makes OpenBLAS retry for ever (a hang, observed at 336 MB
// with 210 MB mapped), so an address-space budget keeps room for that one buffer, unless the
// program mapped it beforehand (reserve_blas_buffers: then it is in VmSize too).
double blas_buffer_room() { return reserved_blas_buffers() > 0 ? 0.0 : OPENBLAS_BUFFER_BYTES; }

// Keeps the smallest budget (a limit already exceeded counts as 0) and says where it comes from;
// @p known false: nothing could be read (a missing /proc file, no cgroup limit).
void tighten(MemoryBudget& b, double bytes, const std::string& limit, bool known = true) {
  if (!known) return;
  bytes = std::max(0.0, bytes);
  if (b.bytes < 0 || bytes < b.bytes) b = {bytes, limit};
}

std::string gigabytes(double bytes, int digits = 2);

}  // namespace

MemoryBudget cgroup_memory_budget(const std::string& root) {
  MemoryBudget b;
  std::ifstream in(root + "/proc/self/cgroup");
  // Lines "ID:CONTROLLERS:PATH": cgroup v2 is "0::PATH"; v1 lists "memory" among the controllers.
  for (std::string line; std::getline(in, line);) {
    const size_t c1 = line.find(':'), c2 = c1 == std::string::npos ? c1 : line.find(':', c1 + 1);
    if (c2 == std::string::npos) continue;
    const std::string controllers = line.substr(c1 + 1, c2 - c1 - 1), path = line.substr(c2 + 1);
    const bool v2 = controllers.empty();
    bool memory = v2;
    for (size_t a = 0; !memory && a <= controllers.size();) {
      const size_t e = std::min(controllers.find(',', a), controllers.size());
      memory = controllers.substr(a, e - a) == "memory";
      a = e + 1;
    }
    if (!memory) continue;
    const std::string base = root + (v2 ? "/sys/fs/cgroup" : "/sys/fs/cgroup/memory");
    const char* limit_file = v2 ? "memory.max" : "memory.limit_in_bytes";
    const char* usage_file = v2 ? "memory.current" : "memory.usage_in_bytes";
    // The process's own group and every group above it may set a limit; inside a container the
    // group's path is often not visible, and the mount's root holds the container's limit.
    std::filesystem::path dir = std::filesystem::path(base) / std::filesystem::path(path).relative_path();
    for (int depth = 0; depth < 64; ++depth) {
      const double limit = read_number((dir / limit_file).string());
      // v1 writes "no limit" as a huge number (PAGE_COUNTER_MAX · page size, ~9.2e18).
      if (limit > 0 && limit < 1e18) {
        // The usage counts the page cache, which the kernel reclaims before it refuses memory:
        // the inactive file pages are taken off it, as Docker and the kubelet do.
        double inactive = 0;
        std::ifstream stat((dir / "memory.stat").string());
        for (std::string k; stat >> k;) {
          double v = 0;
          stat >> v;
          if (k == (v2 ? "inactive_file" : "total_inactive_file")) inactive = v;
        }
        const double used = std::max(0.0, read_number((dir / usage_file).string()) - inactive);
        tighten(b, limit - used,
                "the cgroup memory limit (" + (dir / limit_file).string() + " = " + gigabytes(limit) + ", " +
                    gigabytes(used) + " in use)");
      }
      if (dir.string().size() <= base.size() || !dir.has_parent_path() || dir == dir.parent_path()) break;
      dir = dir.parent_path();
    }
  }
  return b;
}

MemoryBudget memory_budget() {
  MemoryBudget b;
  const double available = proc_kb("/proc/meminfo", "MemAvailable:");
  tighten(b, available, "available on the machine (MemAvailable)", available >= 0);
  // ulimit -v and ulimit -d count address space, not resident memory: what is mapped already
  // (the libraries, thread stacks, the heap so far) is taken off the limit.
  struct rlimit rl {};
  if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
    const double mapped = std::max(0.0, proc_kb("/proc/self/status", "VmSize:"));
    const double room = blas_buffer_room();
    tighten(b, static_cast<double>(rl.rlim_cur) - mapped - room,
            "the address-space limit (ulimit -v, RLIMIT_AS = " + gigabytes(static_cast<double>(rl.rlim_cur)) + ", " +
                gigabytes(mapped) + " mapped" + (room > 0 ? ", " + gigabytes(room) + " kept for OpenBLAS)" : ")"));
  }
  if (getrlimit(RLIMIT_DATA, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
    const double data = std::max(0.0, proc_kb("/proc/self/status", "VmData:"));
    tighten(b, static_cast<double>(rl.rlim_cur) - data - blas_buffer_room(),
            "the data-segment limit (ulimit -d, RLIMIT_DATA = " + gigabytes(static_cast<double>(rl.rlim_cur)) + ", " +
                gigabytes(data) + " in use)");
  }
  const MemoryBudget cg = cgroup_memory_budget("");
  tighten(b, cg.bytes, cg.limit, cg.bytes >= 0);
  return b;
}

namespace {

std::string gigabytes(double bytes, int digits) {
  char buf[48];
  std::snprintf(buf, sizeof buf, bytes < 1e12 ? "%.*g GB" : "%.*e GB", bytes < 1e12 ? digits : digits - 1, bytes / 1e9);
  return buf;
}


// The solver works with products of the problem's scales (energies ~ f·u, squared residuals):
// a stiffness or load near the ends of the double range (a denormal E, loads.scale = 1e-300)
// turns them into 0 or inf and Ipopt into Invalid_Number_Detected, with NaN in the results.
// Refused here with the scale and the key, within 1e-150..1e150 (squares stay normal doubles).
void check_scales(const Model& md) {
  const auto out_of_range = [](double v) { return !(v >= 1e-150 && v <= 1e150); };
  const auto show = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return std::string(buf);
  };
  const double K_s = !md.Kx.empty() && md.Kx.rows() ? md.Kx.diagonal().cwiseAbs().maxCoeff() : 1.0;
  const double F_s = md.fx.size() ? md.fx.cwiseAbs().maxCoeff() : 0.0;
  const char* units = "; rescale the units (e.g. MPa and mm) so that it lies within 1e-150..1e150";
  if (out_of_range(K_s)) input_error("material.E: the stiffness scale (largest K_ii) is " + show(K_s) + units);
  if (F_s == 0) return;  // no load: u = 0 whatever the stiffness
  if (out_of_range(F_s))
    input_error("loads (loads.scale, body_force, tractions): the load scale (largest nodal force) is " + show(F_s) +
                units);
  if (out_of_range(F_s / K_s) || out_of_range(F_s * F_s / K_s))
    input_error("loads and material.E: the displacement scale |f|/K is " + show(F_s / K_s) +
                " and the energy scale " + show(F_s * F_s / K_s) + units);
}

}  // namespace

double dense_gamma3_memory(double gamma3_nodes, int dim) {
  // The condensation's two dense m × m blocks (L_CC and S, m = d·Γ3 nodes; fem/condensation.cpp)
  // and one more of the same size held meanwhile (the smallness check's condensation, the exact
  // solver's and the backends' dense copies). A long thin strip is all Γ3: 20000 × 1 cells have
  // 40 002 Γ3 unknowns, 12.8 GB per matrix; it died with bad_alloc before this term.
  const double m = dim * std::max(0.0, gamma3_nodes);
  return 3.0 * 8.0 * m * m;
}

double estimate_solve_memory(double nodes, int dim, double gamma3_nodes) {
  return estimate_sparse_memory(nodes, dim) + dense_gamma3_memory(gamma3_nodes, dim);
}

double estimate_sparse_memory(double nodes, int dim) {
  const double n = std::max(1.0, dim * nodes);  // unknowns
  // Peak resident memory of a default `solve` (sparse Cholesky fill dominates), fitted to runs
  // of the fig2 scene ('right' mesh) and the 3D box scene on this kind of machine:
  //   2D: 132k unknowns 0.30 GB, 2.1M 4.0-4.5 GB  → 102 B · n · log2 n (fill of a planar
  //       graph under nested dissection grows like n log n);
  //   3D: 14k unknowns 0.18 GB, 45k 0.65 GB       → 370 B · n^(4/3) (fill of a 3D grid);
  // plus 0.1 GB for the program and its libraries.
  const double fill = dim == 2 ? 102.0 * n * std::log2(n) : 370.0 * std::pow(n, 4.0 / 3.0);
  return 1e8 + fill;
}

double estimate_petsc_memory(double nodes, int dim) {
  const double n = std::max(1.0, dim * nodes);
  // The petsc engine keeps no factorization: per unknown, its rows of K (changed in place for the
  // Newton matrix), the GAMG hierarchy (translations as near-null space) and the vectors, plus the
  // mesh and a few gathered vectors on every rank: 1.6 KB per unknown measured on 2 ranks and
  // 1.3 KB on one (bench/README.md, petsc_scaling.py: 70^3 box, 1.06M unknowns; 1.5 KB at 10.26M
  // on 2 ranks), plus ~0.1 GB per rank. 2 KB: the rigid modes (solver.petsc.near_null_space, 2.3 KB
  // at 48^3) or a thinner body cost more.
  return 2e8 + 2000.0 * n;
}

// The most significant digits a memory refusal shows to tell what is needed from what is there.
constexpr int MAX_MEMORY_DIGITS = 6;

std::pair<std::string, std::string> distinct_gigabytes(double need, double have) {
  // "needs about 1.1 GB ... 1.1 GB are available" read as a contradiction.
  int digits = 2;
  while (digits < MAX_MEMORY_DIGITS && gigabytes(need, digits) == gigabytes(have, digits)) ++digits;
  return {gigabytes(need, digits), gigabytes(have, digits)};
}

void check_memory(double nodes, int dim, const std::string& size_keys, bool petsc, double gamma3_nodes) {
  const double dense = petsc ? 0.0 : dense_gamma3_memory(gamma3_nodes, dim);
  const double need = petsc ? estimate_petsc_memory(nodes, dim) : estimate_sparse_memory(nodes, dim) + dense;
  const MemoryBudget have = memory_budget();
  if (have.bytes < 0 || need <= have.bytes) return;
  char count[32];
  std::snprintf(count, sizeof count, "%.3g", nodes);
  std::string what = "a mesh of " + std::string(count) + " nodes";
  // The dense Γ3 part dominates: the remedy is a shorter (coarser) Γ3, not only a smaller mesh.
  const bool gamma3 = dense > 0.5 * need;
  if (gamma3) {
    std::snprintf(count, sizeof count, "%.0f", gamma3_nodes);
    what += " with " + std::string(count) + " Γ3 nodes (dense condensed Γ3 matrices: " + gigabytes(dense) + ")";
  }
  const auto [need_text, have_text] = distinct_gigabytes(need, have.bytes);
  input_error(size_keys + ": " + what + " needs about " + need_text + " to solve, and " + have_text +
              " are available: " + have.limit + "; " +
              (gamma3 ? "use fewer Γ3 nodes (a shorter boundary.gamma3 or a coarser mesh along it), or "
                        "solver.formulation = full with check.smallness = false (no dense Γ3 matrices)"
                      : "lower " + size_keys.substr(0, size_keys.find(" ="))));
}

namespace {

// The generator's parameters of a scene's mesh block (type box, rectangle).
BoxSpec box_spec(const json& m) {
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
  return s;
}

RectangleSpec rectangle_spec(const json& m) {
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
  s.grade_x = parse_grade_towards(m.at("grading").at("x").get<std::string>(), "mesh.grading.x");
  s.grade_y = parse_grade_towards(m.at("grading").at("y").get<std::string>(), "mesh.grading.y");
  s.grading_power = m.at("grading").at("power").get<double>();
  s.perturb = m.at("perturb").get<double>();
  s.seed = m.at("seed").get<unsigned>();
  return s;
}

}  // namespace

Mesh build_mesh(const json& scene, const std::string& scene_dir) {
  const json& m = scene.at("mesh");
  const bool petsc = scene.at("solver").at("engine") == "petsc";
  Mesh mesh;
  auto t0 = clk::now();
  if (m.at("type") == "gmsh") {
    if (m.at("file").is_null()) input_error("mesh.file: required when mesh.type is 'gmsh'");
    const std::string p = scene_path_of(m.at("file").get<std::string>(), scene_dir);
    mesh = read_gmsh(p, m.at("allow_scripts").get<bool>());
    check_memory(static_cast<double>(mesh.num_nodes()), mesh.dim, "mesh.file '" + p + "'", petsc);
  } else if (m.at("type") == "box") {
    // Before the mesh is generated: 1e6 cells a side must be refused, not allocated.
    check_memory((m.at("nx").get<double>() + 1) * (m.at("ny").get<double>() + 1) * (m.at("nz").get<double>() + 1), 3,
                 m.at("n").is_null() ? "mesh.nx, mesh.ny, mesh.nz" : "mesh.n = " + m.at("n").dump(), petsc);
    mesh = make_box(box_spec(m));
  } else {
    check_memory((m.at("nx").get<double>() + 1) * (m.at("ny").get<double>() + 1), 2,
                 m.at("n").is_null() ? "mesh.nx, mesh.ny" : "mesh.n = " + m.at("n").dump(), petsc);
    mesh = make_rectangle(rectangle_spec(m));
  }
  log_debug() << "mesh: " << mesh.origin << " (" << since(t0) << " s)";
  assign_scene_boundary(mesh, scene);
  return mesh;
}

std::string slab_refusal(const json& scene) {
  const json& m = scene.at("mesh");
  const std::string type = m.at("type").get<std::string>();
  if (type != "box" && type != "rectangle") return "mesh.type = " + type + " (only generated boxes and rectangles)";
  if (m.at("perturb").get<double>() > 0) return "mesh.perturb > 0 (its draws run over the whole mesh)";
  if (type == "rectangle") {
    const RectangleSpec s = rectangle_spec(m);
    if (s.diagonal == Diagonal::CROSSED || (s.diagonal == Diagonal::SYMMETRIC && s.nx % 2 == 1))
      return "crossed cells (mesh.diagonal; their centre nodes are not on the grid)";
  }
  return "";
}

SlabCut slab_cut(const json& scene) {
  const json& m = scene.at("mesh");
  if (m.at("type") == "box") return {1, box_spec(m).ny};
  return {0, rectangle_spec(m).nx};
}

long slab_global_node(const json& scene, int c0, int c1, Index v) {
  const json& m = scene.at("mesh");
  // mesh/slabs.hpp's numbering: a box slab's node (i, j, k) is (k·(c1 − c0 + 1) + j − c0)·(nx + 1) + i,
  // a rectangle slab's grid node (i, j) is j·(c1 − c0 + 1) + i − c0.
  const long held = c1 - c0 + 1, u = static_cast<long>(v);
  if (m.at("type") == "box") {
    const BoxSpec s = box_spec(m);
    const long row = s.nx + 1, i = u % row, j = (u / row) % held + c0, k = u / row / held;
    return (k * (s.ny + 1) + j) * row + i;
  }
  const RectangleSpec s = rectangle_spec(m);
  return u / held * (s.nx + 1) + u % held + c0;
}

namespace {

BoundarySpec scene_boundary_spec(const json& scene) {
  const double scale = scene.at("loads").at("scale").get<double>();
  BoundarySpec spec;
  spec.gamma1 = selectors(scene.at("boundary").at("gamma1"), "gamma1", scale);
  spec.gamma2 = selectors(scene.at("boundary").at("gamma2"), "gamma2", scale);
  spec.gamma3 = selectors(scene.at("boundary").at("gamma3"), "gamma3", scale);
  spec.rollers = selectors(scene.at("boundary").at("rollers"), "rollers", scale);
  return spec;
}

}  // namespace

std::vector<std::string> boundary_selector_names(const json& scene) {
  std::vector<std::string> out;
  const BoundarySpec spec = scene_boundary_spec(scene);
  for (const auto* list : {&spec.gamma1, &spec.gamma2, &spec.gamma3, &spec.rollers})
    for (const auto& b : *list) out.push_back(b.context);
  return out;
}

Mesh build_slab_mesh(const json& scene, int c0, int c1, std::vector<long>& counts) {
  const json& m = scene.at("mesh");
  Mesh mesh;
  RowMat lo, hi;
  if (m.at("type") == "box") {
    const BoxSpec s = box_spec(m);
    mesh = make_box_slab(s, c0, c1);
    lo.resize(1, 3);
    hi.resize(1, 3);
    lo << s.x0, s.y0, s.z0;
    hi << s.x1, s.y1, s.z1;
  } else {
    const RectangleSpec s = rectangle_spec(m);
    mesh = make_rectangle_slab(s, c0, c1);
    lo.resize(1, 2);
    hi.resize(1, 2);
    lo << s.x0, s.y0;
    hi << s.x1, s.y1;
  }
  check_cells(mesh);
  counts = assign_boundary_in_box(mesh, scene_boundary_spec(scene), lo, hi);
  return mesh;
}

Mesh build_block_mesh(const json& scene, const BlockRange& b, std::vector<long>& counts) {
  const json& m = scene.at("mesh");
  if (m.at("type") != "box") throw Error("build_block_mesh: only a box is made in blocks", EXIT_INTERNAL);
  const BoxSpec s = box_spec(m);
  Mesh mesh = make_box_block(s, b.i0, b.i1, b.j0, b.j1);
  RowMat lo(1, 3), hi(1, 3);
  lo << s.x0, s.y0, s.z0;
  hi << s.x1, s.y1, s.z1;
  check_cells(mesh);
  counts = assign_boundary_in_box(mesh, scene_boundary_spec(scene), lo, hi);
  return mesh;
}

long block_global_node(const json& scene, const BlockRange& b, Index v) {
  // mesh/slabs.hpp's numbering: a block's node (i, j, k) is (k·(j1 − j0 + 1) + j − j0)·(i1 − i0 + 1) + i − i0.
  const BoxSpec s = box_spec(scene.at("mesh"));
  const long wi = b.i1 - b.i0 + 1, wj = b.j1 - b.j0 + 1, u = static_cast<long>(v);
  const long i = u % wi + b.i0, j = (u / wi) % wj + b.j0, k = u / wi / wj;
  return (k * (s.ny + 1) + j) * (s.nx + 1) + i;
}

void assign_scene_boundary(Mesh& mesh, const json& scene) {
  check_cells(mesh);
  assign_boundary(mesh, scene_boundary_spec(scene));
}

Model build_model(const json& scene, const std::string& scene_dir, bool stiffness) {
  auto t0 = clk::now();
  Mesh mesh = build_mesh(scene, scene_dir);
  const double t_mesh = since(t0);
  Model md = build_model(scene, std::move(mesh), stiffness);
  md.timings["mesh"] = t_mesh;
  return md;
}

Model build_model(const json& scene, Mesh mesh, bool stiffness, bool piece, const GivenBoundary* given) {
  Model md;
  md.scene = scene;
  md.mesh = std::move(mesh);
  const int d = md.mesh.dim;

  md.material = make_material(scene.at("material"), d);

  md.gap = make_gap(scene.at("contact").at("gap"));
  // The gap table's coordinate must exist on this mesh (a 2D point has no z: reading it would be
  // out of bounds and g would vary at random).
  if (!md.gap.points.empty() && md.gap.axis >= d)
    input_error("contact.gap.along: '" + scene.at("contact").at("gap").at("along").get<std::string>() + "' on a " +
                std::to_string(d) + "D mesh (its axes are " + (d == 2 ? "x, y" : "x, y, z") + ")");
  md.normal_law = make_normal_law(scene.at("contact").at("normal_law"));
  md.friction = make_friction_bound(scene.at("contact").at("friction"), md.normal_law);

  md.clamped = clamped_nodes(md.mesh);
  if (given)  // a piece's ghosts: their owners' clamping and rollers
    for (size_t i = 0; i < given->node.size(); ++i) {
      md.clamped[static_cast<size_t>(given->node[i])] = given->clamped[i] != 0;
      if (given->held[i] != 0 || !md.mesh.node_fixed.empty()) {
        if (md.mesh.node_fixed.empty()) md.mesh.node_fixed.assign(static_cast<size_t>(md.mesh.num_nodes()), 0);
        md.mesh.node_fixed[static_cast<size_t>(given->node[i])] = given->held[i];
      }
    }
  md.contact = make_contact_nodes(md.mesh, md.clamped, md.gap, given);
  const bool has_contact_law = md.normal_law || md.friction || !md.gap.is_infinite();
  if (md.contact.size() == 0 && has_contact_law && !piece)
    input_error("boundary.gamma3: the scene defines a contact law but Γ3 has no free node");
  // Γ3 is known now: the cholmod engine's dense condensed matrices join the estimate (the mesh
  // alone passed before it was generated).
  // The dense matrices exist when the problem is condensed onto Γ3 (also the polish's and the exact
  // solver's) or the smallness check condenses the Gram matrix.
  const std::string formulation = scene.at("solver").at("formulation").get<std::string>();
  const bool dense = formulation == "condensed" || (formulation == "auto" && md.material->is_linear()) ||
                     scene.at("check").at("smallness").get<bool>();
  if (scene.at("solver").at("engine") != "petsc")
    check_memory(static_cast<double>(md.mesh.num_nodes()), d, "mesh (" + md.mesh.origin + ")", false,
                 dense ? static_cast<double>(md.contact.size()) : 0.0);
  md.dofs = DofMap(md.mesh, md.clamped, md.contact);

  const auto t0 = clk::now();
  // A nonlinear law's K is its tangent at u = 0 (the small-strain stiffness): it sets the solver's
  // scales and the K(0) energy norm; equilibrium and energies use internal_force / elastic_energy.
  // K_x = Tᵀ K T straight into the free dofs' pattern: the full K is never built. The model keeps
  // its lower triangle, the one copy; both triangles live only here, and go back to the system.
  if (stiffness) {
    md.Kx = SymmetricSpMat(assemble_reduced_stiffness(md.mesh, md.material->tangent(Vec::Zero(voigt_size(d))), md.dofs));
    hand_back_freed_memory(md.dofs.n_free());
  }
  const auto f0v = scene.at("loads").at("body_force").get<std::vector<double>>();
  if (static_cast<int>(f0v.size()) != d) input_error("loads.body_force: expected " + std::to_string(d) + " components");
  const Vec f0 = scene.at("loads").at("scale").get<double>() * Eigen::Map<const Vec>(f0v.data(), d);
  md.f = assemble_body_force(md.mesh, f0) + assemble_tractions(md.mesh);
  md.fx = md.dofs.to_reduced(md.f);
  md.timings["assembly"] = since(t0);
  check_scales(md);
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
  o.ordering = s.at("ordering").get<std::string>();
  o.engine = s.at("engine").get<std::string>();
  const auto& pe = s.at("petsc");
  o.petsc.ksp_rtol = pe.at("ksp_rtol").get<double>();
  o.petsc.ksp_max_it = pe.at("ksp_max_it").get<int>();
  o.petsc.pc = pe.at("pc").get<std::string>();
  o.petsc.newton_pc = pe.at("newton_pc").get<std::string>();
  o.petsc.near_null_space = pe.at("near_null_space").get<std::string>();
  o.petsc.mesh = pe.at("mesh").get<std::string>();
  o.petsc.acceptable_tol = pe.at("acceptable_tol").get<double>();
  o.petsc.polish_max_iters = pe.at("polish_max_iters").get<int>();
  o.petsc.pc_rebuild = pe.at("pc_rebuild").get<double>();
  o.petsc.options = pe.at("options").get<std::string>();
  const auto& ssn = s.at("ssn");
  o.ssn.max_iters = ssn.at("max_iters").get<int>();
  o.ssn.step_rtol = ssn.at("step_rtol").get<double>();
  o.ssn.tol = ssn.at("tol").get<double>();
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
  o.dense_max_unknowns = scene.at("check").at("dense_max_unknowns").get<Index>();
  o.lanczos_tol = scene.at("check").at("lanczos_tol").get<double>();
  o.lanczos_decide_tol = scene.at("check").at("lanczos_decide_tol").get<double>();
  o.lanczos_max_iter = scene.at("check").at("lanczos_max_iter").get<int>();
  const auto& mc = s.at("method_choice");
  o.method_choice.dense_work = mc.at("dense_work").get<double>();
  o.method_choice.full_factorizations = mc.at("full_factorizations").get<double>();
  o.method_choice.memory_fraction = mc.at("memory_fraction").get<double>();
  o.method_choice.small_fraction = mc.at("small_fraction").get<double>();
  o.method_choice.condensed_below = mc.at("condensed_below").get<double>();
  o.method_choice.full_cheaper_by = mc.at("full_cheaper_by").get<double>();
  o.method_choice.petsc_above = mc.at("petsc_above").get<double>();
  o.method_choice.petsc_restarts_above = mc.at("petsc_restarts_above").get<double>();
  o.certify_below = s.at("continuation").at("certify_below").get<double>();
  o.anderson_memory = s.at("fixed_point").at("anderson_memory").get<int>();
  const auto& ex = s.at("exact");
  o.exact = ex.at("enabled").get<bool>();
  o.exact_inner.tol = ex.at("tol").get<double>();
  o.exact_inner.max_rounds = ex.at("max_rounds").get<int>();
  o.exact_inner.max_halvings = ex.at("max_halvings").get<int>();
  o.exact_inner.polish_above = ex.at("polish_above").get<double>();
  o.exact_stage_max_iter = ex.at("stage_max_iter").get<int>();
  o.exact_stage_tol = ex.at("stage_tol").get<double>();
  o.exact_after_stage = ex.at("after_stage").get<int>();
  o.exact_start = ex.at("start").get<std::string>();
  o.exact_start_fallback = ex.at("fallback").get<bool>();
  o.convexity_max_unknowns = ex.at("convexity_max_unknowns").get<Index>();
  return o;
}

}  // namespace hemicontact
