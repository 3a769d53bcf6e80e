// The 3D paper scene (problems/sofonea2017-3d.json) through the whole pipeline: certificate after the
// 3D polish, mirror symmetry of statuses and slip directions about x = 1/2 and y = 1/2, backends
// agreeing, the 3D output columns, and the 3D scene checks (plane, n → nz).
#include <hemicontact/config.hpp>
#include <hemicontact/check/certificate.hpp>
#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/output/csv_writer.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/output/vtk_writer.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include "../support/cli_runner.hpp"
#include "../support/expect_error.hpp"
#include "../support/polish_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>

using namespace hemicontact;
using hemicontact::test::expect_input_error;
using json = nlohmann::json;

namespace {

struct Solved3D {
  Model md;
  SolveOptions opt;
  Solution sol;
};

Solved3D solve_3d(const std::vector<std::string>& overrides) {
  const json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json", overrides);
  Solved3D s{build_model(scene, HEMICONTACT_SOURCE_DIR "/problems"), solve_options_from_scene(scene), {}};
  s.sol = solve(s.md, s.opt);
  return s;
}

// Contact index of the Γ3 node at the mirror image of node k (axis 0: x → 1 − x, 1: y → 1 − y).
Index mirror(const Model& md, Index k, int axis) {
  Eigen::RowVectorXd p = md.mesh.points.row(md.contact.node[k]);
  p[axis] = 1.0 - p[axis];
  for (Index j = 0; j < md.contact.size(); ++j)
    if ((md.mesh.points.row(md.contact.node[j]) - p).norm() < 1e-12) return j;
  return -1;
}

}  // namespace

TEST(Scene3D, CertifiedSymmetricWithCentreStick) {
  const Solved3D s = solve_3d({"mesh.n=6"});
  const Solution& sol = s.sol;
  ASSERT_TRUE(sol.ok()) << sol.message;
  EXPECT_LE(sol.certificate.max_residual, 1e-8);
  EXPECT_TRUE(hemicontact::test::polished_or_at_roundoff(sol));
  ASSERT_EQ(s.md.contact.size(), 7 * 7);
  const auto counts = sol.status_counts();
  // Fig. 2 in 3D: the centre node sticks, every other node slips; both layer regimes occur.
  EXPECT_EQ(counts.at("stick"), 1);
  EXPECT_EQ(counts.at("slip"), 48);
  EXPECT_GT(counts.at("contact"), 0);
  EXPECT_GT(counts.at("compliance"), 0);
  const double U = sol.certificate.length_scale;
  for (Index k = 0; k < s.md.contact.size(); ++k) {
    const auto p = s.md.mesh.points.row(s.md.contact.node[k]);
    if (std::abs(p[0] - 0.5) < 1e-12 && std::abs(p[1] - 0.5) < 1e-12) {
      EXPECT_EQ(sol.status[k].str(), "contact/stick");
    }
    const SlipDirection d = slip_direction(s.md, sol.state, k);
    for (int axis = 0; axis < 2; ++axis) {
      const Index j = mirror(s.md, k, axis);
      ASSERT_GE(j, 0);
      EXPECT_EQ(sol.status[k].str(), sol.status[j].str());
      // The symmetric mesh and loads: u_ν equal, u_τ mirrored (to the solve's accuracy).
      EXPECT_NEAR(sol.state.u_nu[k], sol.state.u_nu[j], 1e-9 * U);
      Eigen::RowVectorXd ut = sol.state.u_tau_vec.row(j);
      ut[axis] = -ut[axis];
      EXPECT_NEAR((sol.state.u_tau_vec.row(k) - ut).norm(), 0.0, 1e-9 * U);
    }
    if (sol.status[k].tangential == TangentialStatus::SLIP) {
      // Bottom face, ν = −e_z: the angle is atan2(d_y, d_x) of the top view; the slip is outward
      // (away from the centre) in x wherever the node is off the centre line x = 1/2.
      EXPECT_NEAR(d.dir.norm(), 1.0, 1e-14);
      EXPECT_NEAR(d.dir.z(), 0.0, 1e-14);
      EXPECT_NEAR(d.angle_deg, std::atan2(d.dir.y(), d.dir.x()) * 180 / M_PI, 1e-12);
      if (std::abs(p[0] - 0.5) > 1e-12) {
        EXPECT_GT(d.dir.x() * (p[0] - 0.5), 0.0);
      }
    }
  }
}

// Every backend family solves the 3D scene to the same answer; the local NLopt ones at tol 1e-6
// are then polished (3D Newton on the statuses) to the same certified solution.
TEST(Scene3D, BackendsAgree) {
  if (!HEMICONTACT_HAS_IPOPT) GTEST_SKIP() << "built without Ipopt (coinor-libipopt-dev): the comparison needs both backends";
  const Solved3D ref = solve_3d({"mesh.n=4", "solver.backend=ipopt"});
  ASSERT_TRUE(ref.sol.ok()) << ref.sol.message;
  const double U = ref.sol.certificate.length_scale;
  for (const std::string b : {"newton", "nlopt:LD_LBFGS", "nlopt:LD_MMA"}) {
    SCOPED_TRACE(b);
    std::vector<std::string> o = {"mesh.n=4", "solver.backend=" + b};
    if (b.rfind("nlopt", 0) == 0) o.push_back("solver.tol=1e-6");
    const Solved3D s = solve_3d(o);
    ASSERT_TRUE(s.sol.ok()) << s.sol.message;
    EXPECT_LE(s.sol.certificate.max_residual, 1e-8);
    EXPECT_LE((s.sol.u - ref.sol.u).cwiseAbs().maxCoeff(), 1e-8 * U);
  }
  // The full (uncondensed) formulation needs no polish to pass with the projected Newton backend.
  const Solved3D full = solve_3d({"mesh.n=4", "solver.backend=newton", "solver.formulation=full"});
  ASSERT_TRUE(full.sol.ok()) << full.sol.message;
  EXPECT_LE((full.sol.u - ref.sol.u).cwiseAbs().maxCoeff(), 1e-8 * U);
}

// 3D outputs: report.json nodes carry slip_dir (unit, null when sticking) and slip_angle_deg;
// gamma3.csv has the 3D columns after the 2D ones.
TEST(Scene3D, ReportAndCsvCarryTheSlipDirection) {
  const Solved3D s = solve_3d({"mesh.n=2"});
  ASSERT_TRUE(s.sol.ok()) << s.sol.message;
  const json r = make_report(s.md, s.sol, s.opt);
  ASSERT_EQ(r["nodes"].size(), 9u);
  for (const auto& n : r["nodes"]) {
    if (n["status"].get<std::string>().find("stick") != std::string::npos) {
      EXPECT_TRUE(n["slip_dir"].is_null());
    } else {
      const auto d = n["slip_dir"].get<std::vector<double>>();
      EXPECT_NEAR(std::hypot(d[0], d[1], d[2]), 1.0, 1e-14);
      EXPECT_NEAR(n["slip_angle_deg"].get<double>(), std::atan2(d[1], d[0]) * 180 / M_PI, 1e-12);
    }
  }
  std::mt19937 rng(std::random_device{}());
  const auto path = std::filesystem::temp_directory_path() / ("hemicontact_scene3d_" + std::to_string(rng()) + ".csv");
  write_gamma3_csv(path.string(), s.md, s.sol);
  std::ifstream f(path);
  std::string header;
  std::getline(f, header);
  EXPECT_EQ(header,
            "index,node,x,y,z,w,g,u_nu,u_tau,sigma_nu,sigma_tau,xi,lambda,status,slip_dir_x,slip_dir_y,"
            "slip_dir_z,slip_angle_deg");
  std::filesystem::remove(path);
  // The VTU has the 3D status fields.
  const auto vtu = std::filesystem::temp_directory_path() / ("hemicontact_scene3d_" + std::to_string(rng()) + ".vtu");
  write_vtu(vtu.string(), s.md, s.sol);
  std::ifstream v(vtu);
  const std::string text((std::istreambuf_iterator<char>(v)), std::istreambuf_iterator<char>());
  for (const char* name :
       {"\"slip_dir\" NumberOfComponents=\"3\"", "\"slip_angle_deg\"", "\"status_normal\"", "\"status_tangential\""})
    EXPECT_NE(text.find(name), std::string::npos) << name;
  std::filesystem::remove(vtu);
}

TEST(Scene3D, SceneChecks) {
  const json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json", {"mesh.n=3"});
  EXPECT_EQ(scene["mesh"]["nz"], 3);
  // Odd n with the symmetric pattern: the box generator says why.
  expect_input_error([&] { build_model(scene, "."); }, {"mesh.pattern", "even nx and ny"});
  const json strain =
      load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json", {"mesh.n=2", "material.plane=strain"});
  expect_input_error([&] { build_model(strain, "."); }, {"material.plane", "3D"});
  // A 2D traction on a 3D mesh names the selector.
  const json t2 = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json",
                             {"mesh.n=2", "boundary.gamma2.0.traction=[1,0]"});
  expect_input_error([&] { build_model(t2, "."); }, {"boundary.gamma2[0].traction", "3 components"});
}

// `hemicontact solve --plot` on a 3D scene draws the Γ3 status map (scripts/plot_status3d.py)
// instead of the 2D Fig. 2 picture.
TEST(Scene3D, CliPlotDrawsTheStatusMap) {
  if (!hemicontact::test::matplotlib_available()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  std::mt19937 rng(std::random_device{}());
  const auto dir = std::filesystem::temp_directory_path() / ("hemicontact_scene3d_plot_" + std::to_string(rng()));
  std::filesystem::create_directories(dir);
  const auto r = hemicontact::test::run_cli(dir,
                                            "solve " HEMICONTACT_SOURCE_DIR
                                            "/problems/sofonea2017-3d.json --set mesh.n=4 --quiet --plot --out " +
                                                (dir / "res").string(),
                                            "HEMICONTACT_SCRIPTS=" HEMICONTACT_SOURCE_DIR "/scripts");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "res" / "status3d.png")) << r.out << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "res" / "fig2.png"));
  std::filesystem::remove_all(dir);
}
