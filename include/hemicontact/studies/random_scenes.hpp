#pragma once
/// @file random_scenes.hpp  Randomized stress scenes with fixed seeds: parameters drawn over
/// realistic and extreme ranges, written as `--set` overrides of problems/sofonea2017-fig2.json so
/// that any seed can be rerun from the command line. Shared by tests/stress/random_test.cpp (fast
/// part), bench/stress_report.cpp and bench/random_study.cpp (full part) and the Python module
/// (hemicontact.random_scene): shipped with the library, so that the module needs nothing of tests/.
///
/// Portability: std::mt19937's output sequence is fixed by the standard, the library's
/// distributions are not (libstdc++ and libc++ differ), so every draw maps raw 32-bit outputs
/// itself: u = (k + 0.5)/2³² ∈ (0, 1).

#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace hemicontact::stress {

/// Uniform draws in (0, 1) and friends from raw mt19937 output (portable across libraries).
class Draw {
 public:
  explicit Draw(std::uint32_t seed) : m_rng(seed) {}
  double u() { return (static_cast<double>(m_rng()) + 0.5) / 4294967296.0; }
  double uniform(double a, double b) { return a + (b - a) * u(); }
  double log_uniform(double lo, double hi) { return std::pow(10.0, uniform(std::log10(lo), std::log10(hi))); }
  int integer(int lo, int hi) { return lo + static_cast<int>(std::floor(u() * (hi - lo + 1))); }  // [lo, hi]

 private:
  std::mt19937 m_rng;
};

/// One random scene: the overrides, and the drawn values for the report.
struct RandomScene {
  unsigned seed = 0;
  std::vector<std::string> overrides;
  double E = 0, nu = 0, load_scale = 1, c1 = 0, mu = 0, g = 0, eps = 0, perturb = 0, aspect = 1;
  bool plane_strain = false, gap_none = false, loads_consistent = false;
  int n = 0;
  /// The command line that reruns this scene.
  std::string command() const {
    std::string c = "hemicontact solve problems/sofonea2017-fig2.json";
    for (const auto& o : overrides) c += " --set '" + o + "'";
    return c;
  }
};

inline std::string num(double x) {
  std::ostringstream os;
  os.precision(17);
  os << x;
  return os.str();
}

/// Draw scene @p seed on an n_min..n_max mesh (cells across the height).
///   E ∈ [1e-3, 1e9] log-uniform; loads × E/2000 (consistent: same u as fig2) or × a log-uniform
///   factor in [1e-3, 1e3] relative to that (inconsistent: the contact regime changes);
///   κ ∈ [0, 0.499], plane stress or strain; c1 ∈ [1e-2, 1e8] log-uniform, r1 ∈ [1e-3, 1],
///   r2 ∈ r1·[1.2, 2.2], c2 ∈ [−c1 r1/(r2 − r1), 0] (p_ν(r2) ≥ 0: F_b = μ p_ν stays ≥ 0 by (15c)),
///   c3 ∈ c1·[0.1, 10]; μ ∈ [0, 5]; g = 0, none, or log-uniform in [1e-4, 10]; ε_τ = ε_ν ∈
///   [1e-12, 1e-2] log-uniform; perturb ∈ [0, 0.3]; aspect (x length) ∈ [1, 100] log-uniform.
inline RandomScene draw_scene(unsigned seed, int n_min, int n_max) {
  Draw d(seed);
  RandomScene s;
  s.seed = seed;
  s.n = d.integer(n_min, n_max);
  s.E = d.log_uniform(1e-3, 1e9);
  s.loads_consistent = d.u() < 0.5;
  s.load_scale = s.E / 2000 * (s.loads_consistent ? 1.0 : d.log_uniform(1e-3, 1e3));
  s.plane_strain = d.u() < 0.5;
  s.nu = d.uniform(0, 0.499);
  s.c1 = d.log_uniform(1e-2, 1e8);
  const double r1 = d.log_uniform(1e-3, 1), r2 = r1 * d.uniform(1.2, 2.2);
  const double c2 = -d.u() * s.c1 * r1 / (r2 - r1), c3 = s.c1 * d.log_uniform(0.1, 10);
  s.mu = d.uniform(0, 5);
  const double gu = d.u();
  s.gap_none = gu < 0.2;
  s.g = gu < 0.2 ? INFINITY : gu < 0.4 ? 0.0 : d.log_uniform(1e-4, 10);
  s.eps = d.log_uniform(1e-12, 1e-2);
  s.perturb = d.uniform(0, 0.3);
  s.aspect = d.log_uniform(1, 100);
  const char* diagonals[] = {"right", "left", "symmetric", "crossed"};
  const std::string diagonal = diagonals[d.integer(0, 3)];
  const int nx = std::min(8 * s.n, std::max(s.n, static_cast<int>(std::lround(s.n * s.aspect))));
  s.overrides = {"mesh.n=null",
                 "mesh.x=[0," + num(s.aspect) + "]",
                 "mesh.nx=" + std::to_string(nx),
                 "mesh.ny=" + std::to_string(s.n),
                 "mesh.diagonal=" + diagonal,
                 "mesh.perturb=" + num(s.perturb),
                 "mesh.seed=" + std::to_string(seed),
                 "material.E=" + num(s.E),
                 "material.nu=" + num(s.nu),
                 std::string("material.plane=") + (s.plane_strain ? "strain" : "stress"),
                 "loads.scale=" + num(s.load_scale),
                 "contact.normal_law.c1=" + num(s.c1),
                 "contact.normal_law.c2=" + num(c2),
                 "contact.normal_law.c3=" + num(c3),
                 "contact.normal_law.r1=" + num(r1),
                 "contact.normal_law.r2=" + num(r2),
                 "contact.friction.mu=" + num(s.mu),
                 "contact.gap=" + (s.gap_none ? std::string("null") : num(s.g)),
                 "solver.eps_tau=" + num(s.eps),
                 "solver.eps_nu=" + num(s.eps),
                 "check.smallness=false"};
  return s;
}

/// Scene @p seed of the default-settings study (bench/random_study.cpp): the physics of draw_scene
/// (E, ν, plane stress/strain, loads, the layer law c1, c2, c3, r1, r2, μ, g, the mesh, its
/// perturbation and aspect; realistic and extreme alike) with NO solver override: ε, iteration caps
/// and tolerances stay at their defaults. check.smallness stays off (a diagnostic, timed apart).
inline RandomScene draw_default_scene(unsigned seed, int n_min, int n_max) {
  RandomScene s = draw_scene(seed, n_min, n_max);
  std::vector<std::string> o;
  for (const auto& x : s.overrides)
    if (x.rfind("solver.", 0) != 0) o.push_back(x);
  s.overrides = o;
  s.eps = 0;  // the default
  return s;
}

}  // namespace hemicontact::stress
