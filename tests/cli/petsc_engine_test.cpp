// The petsc engine end to end: `mpirun -np P hemicontact solve SCENE --set
// solver.engine="petsc"` against the cholmod engine on the paper's scenes (2D fig2, printed, 3D),
// small meshes, P = 1 and 2; then its bad input. In a build without PETSc, the engine asked for
// must be refused naming the package.
//
// Both of the engine's methods are checked: ssn (its default: semismooth Newton on the unsmoothed
// statuses) on every case, TAO's bounded Newton (smoothing continuation, then the polish) on two.
//
// Agreement tolerances: both engines end on the unsmoothed conditions of (22), solved on the same
// statuses to round-off (solver/polish.hpp, the ssn steps and the polish in src/petsc/), so the
// answers differ by the conditioning of the status system times machine precision: κ ~ 1e4 for
// these meshes (h = 1/16, 3D 1/4) gives ~1e-12; 1e-8 is the bound asserted, and the certificate of
// each answer must pass at 1e-8 (check.certificate_tol).
#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>
#include <hemicontact/studies/petsc_process.hpp>
#include <hemicontact/studies/random_scenes.hpp>

#include "support/cli_runner.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>
#include <string>
#include <tuple>
#include <utility>

namespace fs = std::filesystem;
using json = nlohmann::json;
using hemicontact::test::CliOutcome;
using hemicontact::test::matplotlib_available;
using hemicontact::test::run_cli;
using hemicontact::test::slurp;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("hemicontact-petsc-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string problem(const std::string& name) {
  return (fs::path(HEMICONTACT_SOURCE_DIR) / "problems" / (name + ".json")).string();
}

#if HEMICONTACT_HAS_PETSC

// OpenMPI refuses root without these two; --oversubscribe lets -np exceed the machine's cores.
const char* const MPIRUN =
    "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_mpi_yield_when_idle=1 mpirun -np";

CliOutcome run_mpi(const fs::path& dir, int np, const std::string& args) {
  return run_cli(dir, args + " --set solver.engine='\"petsc\"'", std::string(MPIRUN) + " " + std::to_string(np));
}

// One run of @p args on @p np ranks into dir/name; it must exit 0. @return its report.json.
json solved(const fs::path& dir, int np, const std::string& args, const std::string& name) {
  const CliOutcome r = run_mpi(dir, np, args + " --out " + (dir / name).string());
  EXPECT_EQ(r.code, 0) << r.err;
  return r.code == 0 ? json::parse(slurp(dir / name / "report.json")) : json::object();
}

// Two runs that must reach the same answer: both certified, the same statuses, energies to 1e-10.
void expect_same_answer(const json& a, const json& b) {
  ASSERT_TRUE(a.contains("energy") && b.contains("energy"));
  for (const json* r : {&a, &b}) {
    EXPECT_TRUE(r->at("certificate").at("passed").get<bool>());
    EXPECT_LE(r->at("certificate").at("max_residual").get<double>(), 1e-8);
  }
  EXPECT_EQ(a.at("status_counts"), b.at("status_counts"));
  const double ea = a.at("energy").get<double>(), eb = b.at("energy").get<double>();
  EXPECT_LE(std::abs(ea - eb), 1e-10 * std::abs(ea));
}

// The same scene on @p np ranks as given and with @p extra settings, into dir/a and dir/b: the two
// must reach the same answer. @return both reports.
std::pair<json, json> same_answer_twice(const fs::path& dir, int np, const std::string& args, const std::string& extra) {
  std::pair<json, json> r{solved(dir, np, args, "a"), solved(dir, np, args + " " + extra, "b")};
  expect_same_answer(r.first, r.second);
  return r;
}

// A study as auto runs it and on the cholmod engine: each run's outcome and JSON file.
struct BothEngines {
  CliOutcome first, cholmod;
  json a, b;  // empty where that run did not exit 0
};

// @p command (ending in "--out ") as auto runs it, into dir/@p first, and with solver.engine =
// cholmod, into dir/cholmod; both must exit 0. Each run's @p file is read back.
BothEngines on_both_engines(const fs::path& dir, const std::string& command, const std::string& first,
                            const std::string& file) {
  BothEngines r;
  r.first = run_cli(dir, command + (dir / first).string());
  EXPECT_EQ(r.first.code, 0) << r.first.err;
  r.cholmod = run_cli(dir, command + (dir / "cholmod").string() + " --set solver.engine='\"cholmod\"'");
  EXPECT_EQ(r.cholmod.code, 0) << r.cholmod.err;
  if (r.first.code == 0) r.a = json::parse(slurp(dir / first / file));
  if (r.cholmod.code == 0) r.b = json::parse(slurp(dir / "cholmod" / file));
  return r;
}

struct Case {
  std::string scene;
  std::string sets;  // mesh size
  int np;
  std::string backend = "";  // "": the engine's default (ssn)
  std::string layout = "slabs";  // the distributed layout expected (slabs or blocks)
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.scene << " " << c.sets.substr(c.sets.rfind(' ') + 1) << " np=" << c.np << " "
      << (c.backend.empty() ? "ssn" : c.backend);
}

TEST(PetscEngine, BackendsListSsnAndTao) {
  const fs::path dir = scratch("backends");
  const CliOutcome r = run_cli(dir, "backends");
  ASSERT_EQ(r.code, 0);
  for (const char* name : {"ssn", "tao:bnls", "tao:bntr", "tao:bntl"})
    EXPECT_NE(r.out.find(name), std::string::npos) << name;
  fs::remove_all(dir);
}

// solver.engine = auto (the default): `solve` runs the petsc engine in one process for a 3D box
// at or above solver.method_choice.petsc_above unknowns (lowered here to keep the test small), the
// cholmod engine below it, in 2D and where a setting is the cholmod engine's; report.json's
// engine_choice and stdout's first row say which and why, and the answers agree.
TEST(PetscEngine, AutoChoosesTheEngineFromTheScenesSize) {
  const fs::path dir = scratch("engine-auto");
  const std::string box = "solve " + problem("sofonea2017-3d") + " --set mesh.n=4 --set output.vtu=false";
  std::map<std::string, std::string> stdout_of;
  const auto report = [&](const std::string& args, const std::string& name) {
    const CliOutcome r = run_cli(dir, args + " --out " + (dir / name).string());
    EXPECT_EQ(r.code, 0) << name << ": " << r.err;
    stdout_of[name] = r.out;
    return json::parse(slurp(dir / name / "report.json"));
  };
  const json big = report(box + " --set solver.method_choice.petsc_above=300", "big");
  const json small = report(box, "small");
  const json named = report(box + " --set solver.method_choice.petsc_above=300 --backend newton", "named");
  const json flat = report("solve " + problem("sofonea2017-fig2") + " --set mesh.n=8 --set solver.method_choice.petsc_above=1", "flat");
  EXPECT_EQ(big.at("engine"), "petsc");
  EXPECT_EQ(big.at("engine_choice").at("engine"), "petsc");
  EXPECT_EQ(big.at("engine_choice").at("automatic"), true);
  EXPECT_NE(big.at("engine_choice").at("reason").get<std::string>().find("petsc_above"), std::string::npos);
  for (const json* r : {&small, &named, &flat}) {
    EXPECT_EQ(r->at("engine_choice").at("engine"), "cholmod") << r->at("engine_choice").dump();
    EXPECT_EQ(r->at("engine_choice").at("automatic"), true);
  }
  EXPECT_NE(named.at("engine_choice").at("reason").get<std::string>().find("solver.backend = newton"), std::string::npos);
  EXPECT_NE(flat.at("engine_choice").at("reason").get<std::string>().find("(2D: the cholmod engine)"), std::string::npos);
  const double e = small.at("energy").get<double>();
  EXPECT_NEAR(big.at("energy").get<double>(), e, 1e-10 * std::abs(e));
  // An explicit engine wins, and says it was given.
  const json given = report(box + " --set solver.method_choice.petsc_above=300 --set solver.engine=cholmod", "given");
  EXPECT_EQ(given.at("engine_choice").at("engine"), "cholmod");
  EXPECT_EQ(given.at("engine_choice").at("automatic"), false);
  // stdout's first row, the same words as engine_choice, before either engine's summary.
  const auto first_row = [&](const std::string& name) { return stdout_of[name].substr(0, stdout_of[name].find('\n')); };
  EXPECT_EQ(first_row("big"), "engine        petsc (auto): " + big.at("engine_choice").at("reason").get<std::string>());
  EXPECT_EQ(first_row("flat"), "engine        cholmod (auto): " + flat.at("engine_choice").at("reason").get<std::string>());
  EXPECT_EQ(first_row("given"), "engine        cholmod: solver.engine = cholmod (given)");
  fs::remove_all(dir);
}

// Where `solve` would take the petsc engine automatically (a 3D box above petsc_above, lowered
// here) and a command stays in this process, its JSON's engine_choice and the log say so with
// solve's reason; below it they say nothing of the kind.
// path restarts one solver from many points in this process: the cholmod engine, saying where
// `solve` would have taken the petsc engine (converge takes it: the next test). minima has its own
// threshold, solver.method_choice.petsc_restarts_above; --backends keeps it here, saying why.
TEST(PetscEngine, InProcessCommandsSayWhereSolveWouldTakeThePetscEngine) {
  const fs::path dir = scratch("engine-in-process");
  const std::string scene = problem("sofonea2017-3d") + " --set output.vtu=false --set output.plot=false";
  const auto study = [&](const std::string& command, const std::string& file, const std::string& name) {
    const CliOutcome r = run_cli(dir, command + " --out " + (dir / name).string());
    EXPECT_EQ(r.code, 0) << name << ": " << r.err;
    return std::make_pair(json::parse(slurp(dir / name / file)).at("engine_choice"), r.err);
  };
  const std::string low = " --set solver.method_choice.petsc_above=50";
  // minima decides by its own threshold (MinimaRunsItsStartsOnThePetscEngineAboveItsThreshold);
  // what needs this process keeps it there and says so.
  const std::string minima = "minima " + scene + " --set mesh.n=2 --starts 1 --load-path-steps 1";
  const auto [stays, stays_log] = study(minima + low, "minima.json", "minima-low");
  EXPECT_EQ(stays.at("engine"), "cholmod");
  EXPECT_NE(stays.at("reason").get<std::string>().find("< solver.method_choice.petsc_restarts_above"),
            std::string::npos)
      << stays.dump();
  const auto [named, named_log] =
      study(minima + " --set solver.method_choice.petsc_restarts_above=50 --backends ipopt", "minima.json", "named");
  EXPECT_EQ(named.at("engine"), "cholmod");
  EXPECT_NE(named.at("reason").get<std::string>().find("minima runs in this process (--backends"), std::string::npos)
      << named.dump();
  for (const auto& [command, file, unknowns] : {std::tuple{"path " + scene + " --set mesh.n=2 --steps 2", "path.json", "81"}}) {
    SCOPED_TRACE(command);
    const auto [above, log] = study(command + low, file, "above");
    EXPECT_EQ(above.at("engine"), "cholmod");
    EXPECT_EQ(above.at("automatic"), true);
    const std::string reason = above.at("reason").get<std::string>();
    EXPECT_NE(reason.find("runs in this process"), std::string::npos) << reason;
    EXPECT_NE(reason.find(std::string("would take the petsc engine: 3D box of ") + unknowns +
                          " unknowns >= solver.method_choice.petsc_above"),
              std::string::npos)
        << reason;
    EXPECT_NE(log.find("engine cholmod (auto): "), std::string::npos) << log;
    const auto [below, log_below] = study(command, file, "below");
    EXPECT_EQ(below.at("engine"), "cholmod");
    EXPECT_EQ(below.at("reason").get<std::string>().find("petsc engine"), std::string::npos) << below.dump();
    fs::remove_all(dir / "above");
    fs::remove_all(dir / "below");
  }
  fs::remove_all(dir);
}

// converge takes the engine `solve` would, level by level: above petsc_above the petsc engine runs
// as a process of its own (hemicontact-mpi --stream) and hands u back, which this process judges.
// Its study must be the cholmod engine's: the same statuses, energy norms and errors to the
// engines' agreement (file comment: 1e-8), every level certified by the in-process judge.
TEST(PetscEngine, ConvergeRunsThePetscEngineWhereSolveWould) {
  const fs::path dir = scratch("converge-petsc");
  const std::string study = "converge " + problem("sofonea2017-3d") +
                            " --set output.vtu=false --set output.plot=false --levels 2,4 --reference 8"
                            " --set solver.method_choice.petsc_above=300 --out ";
  const BothEngines both = on_both_engines(dir, study, "auto", "convergence.json");
  ASSERT_FALSE(both.a.empty() || both.b.empty());
  const json &a = both.a, &b = both.b;
  const CliOutcome& p = both.first;
  EXPECT_EQ(a.at("engine_choice").at("engine"), "petsc") << a.at("engine_choice").dump();
  EXPECT_EQ(b.at("engine_choice").at("engine"), "cholmod");
  // n = 2 (81 unknowns) stays below petsc_above; n = 4 (375) and the reference (2187) are above it.
  EXPECT_EQ(p.err.find("convergence: n = 2: the petsc engine"), std::string::npos) << p.err;
  for (const char* n : {"n = 4: the petsc engine", "n = 8: the petsc engine", "--stream), u judged here"})
    EXPECT_NE(p.err.find(n), std::string::npos) << n << "\n" << p.err;
  json levels_a = a.at("levels"), levels_b = b.at("levels");
  levels_a.push_back(a.at("reference"));
  levels_b.push_back(b.at("reference"));
  ASSERT_EQ(levels_a.size(), 3u);
  ASSERT_EQ(levels_b.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const json &la = levels_a[i], &lb = levels_b[i];
    SCOPED_TRACE("n = " + la.at("n").dump());
    EXPECT_TRUE(la.at("certified").get<bool>());
    EXPECT_LE(la.at("certificate_max_residual").get<double>(), 1e-8);
    EXPECT_EQ(la.at("status_counts"), lb.at("status_counts"));
    const double na = la.at("energy_norm").get<double>(), nb = lb.at("energy_norm").get<double>();
    EXPECT_LE(std::abs(na - nb), 1e-8 * nb);
    EXPECT_LE(std::abs(la.at("error").get<double>() - lb.at("error").get<double>()), 1e-8);
    const bool petsc = la.at("n").get<int>() > 2;
    EXPECT_EQ(la.at("solved_by").get<std::string>().find("PETSc, 1 rank") != std::string::npos, petsc)
        << la.at("solved_by");
  }
  fs::remove_all(dir);
}

// minima takes the petsc engine from solver.method_choice.petsc_restarts_above on: every start a
// process of its own (zero: the engine's own start; the Γ3 starts and the load path from their u),
// judged and second-order checked here. Against the same search in this process: the same
// solution to the engines' agreement, both local minima (the full space's λ_min is not the
// condensed one's, the sign is: Haynsworth), every run certified, no "exact-from-zero" run (the
// in-process exact solver's own path), and minima-runs.csv readable with the engine's name,
// commas and all, in one quoted field.
TEST(PetscEngine, MinimaRunsItsStartsOnThePetscEngineAboveItsThreshold) {
  const fs::path dir = scratch("minima-petsc");
  const std::string search = "minima " + problem("sofonea2017-3d") +
                             " --set mesh.n=4 --starts 2 --load-path-steps 2 --set output.vtu=false"
                             " --set solver.method_choice.petsc_restarts_above=100 --out ";
  const BothEngines both = on_both_engines(dir, search, "petsc", "minima.json");
  ASSERT_FALSE(both.a.empty() || both.b.empty());
  const json &a = both.a, &b = both.b;
  EXPECT_EQ(a.at("engine_choice").at("engine"), "petsc") << a.at("engine_choice").dump();
  EXPECT_NE(a.at("engine_choice").at("reason").get<std::string>().find("petsc_restarts_above"), std::string::npos);
  ASSERT_EQ(a.at("solutions").size(), 1u) << a.at("solutions").dump();
  ASSERT_EQ(b.at("solutions").size(), 1u);
  const json &sa = a.at("solutions")[0], &sb = b.at("solutions")[0];
  const double ea = sa.at("energy").get<double>(), eb = sb.at("energy").get<double>();
  EXPECT_NEAR(ea, eb, 1e-8 * std::abs(eb));
  EXPECT_EQ(sa.at("type"), "local minimum") << sa.at("second_order").dump();
  EXPECT_EQ(sb.at("type"), "local minimum");
  EXPECT_GT(sa.at("second_order").at("lambda_min").get<double>(), 0);
  std::vector<std::string> starts;
  for (const json& r : a.at("runs")) {
    starts.push_back(r.at("start").get<std::string>());
    EXPECT_TRUE(r.at("certified").get<bool>()) << r.dump();
    EXPECT_EQ(r.at("backend"), "petsc engine");
    EXPECT_NE(r.at("solved_by").get<std::string>().find("PETSc"), std::string::npos) << r.dump();
  }
  EXPECT_EQ(starts, (std::vector<std::string>{"zero", "at-gap", "separated", "random-1", "random-2", "load-up",
                                              "load-down"}));
  // minima-runs.csv: ten fields on every row, the quoted ones read whole.
  std::istringstream csv(slurp(dir / "petsc" / "minima-runs.csv"));
  std::string line;
  int rows = 0;
  while (std::getline(csv, line)) {
    int fields = 1;
    bool quoted = false;
    for (const char ch : line) {
      if (ch == '"') quoted = !quoted;
      if (ch == ',' && !quoted) ++fields;
    }
    EXPECT_EQ(fields, 10) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 8);  // the header and seven runs
  fs::remove_all(dir);
}

// hemicontact-mpi's --stream writes no files: what would act on files is refused, and so is the
// scene '-' (stdin) without it; an error of the engine (a nonlinear material) reaches converge's
// caller with its code and message.
TEST(PetscEngine, StreamRefusesFileOptionsAndConvergePassesTheEnginesErrorOn) {
  const fs::path dir = scratch("stream-usage");
  const std::string mpi = (fs::path(HEMICONTACT_CLI_PATH).parent_path() / "hemicontact-mpi").string();
  const auto run = [&](const std::string& args) {
    const int status = std::system(("cd '" + dir.string() + "' && " + mpi + " " + args + " </dev/null >" +
                                    (dir / "o.txt").string() + " 2>" + (dir / "e.txt").string())
                                       .c_str());
    return std::make_pair(WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "e.txt"));
  };
  const auto [with_out, err_out] = run("solve - --stream --out x");
  EXPECT_EQ(with_out, 1);
  EXPECT_NE(err_out.find("--stream writes no files: --out"), std::string::npos) << err_out;
  const auto [follows, err_follows] = run("solve - --mesh-follows --out x");
  EXPECT_EQ(follows, 1);
  EXPECT_NE(err_follows.find("--mesh-follows: one rank, with --stream and the scene '-'"), std::string::npos) << err_follows;
  const auto [no_mesh, err_no_mesh] = run("solve - --stream --mesh-follows");  // stdin is empty
  EXPECT_EQ(no_mesh, 2);
  EXPECT_NE(err_no_mesh.find("--mesh-follows: no mesh after the scene's line"), std::string::npos) << err_no_mesh;
  const auto [start, err_start] = run("solve - --stream --start-follows");
  EXPECT_EQ(start, 1);
  EXPECT_NE(err_start.find("--start-follows: with --mesh-follows only"), std::string::npos) << err_start;
  const auto [dash, err_dash] = run("solve - --out x");
  EXPECT_EQ(dash, 1);
  EXPECT_NE(err_dash.find("the scene '-' (stdin) is read with --stream only"), std::string::npos) << err_dash;
  EXPECT_FALSE(fs::exists(dir / "x"));
  const CliOutcome bad = run_cli(dir, "converge " + problem("sofonea2017-3d") +
                                          " --levels 2 --reference 2 --set solver.engine='\"petsc\"'"
                                          " --set material.model='\"hencky\"' --set material.shear_ratio=0.5"
                                          " --set material.eps_ref=1 --out " +
                                          (dir / "bad").string());
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_NE(bad.err.find("solver.engine = petsc: linear materials only"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("the petsc engine (" + mpi + ") stopped with exit code 2"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "bad" / "convergence.json"));
  fs::remove_all(dir);
}

// Where the petsc engine's program is not found (a library or CLI copied without it; here
// HEMICONTACT_MPI pointing nowhere), auto keeps the cholmod engine and says why; asked for, the
// engine is refused naming the path (exit 2), by solve and converge alike.
TEST(PetscEngine, AProgramNotFoundKeepsAutoOnCholmodAndRefusesAGivenPetsc) {
  const fs::path dir = scratch("program-missing");
  const std::string env = "HEMICONTACT_MPI=" + (dir / "nowhere").string();
  const std::string scene = problem("sofonea2017-3d") + " --set output.vtu=false --set output.plot=false" +
                            " --set mesh.n=2 --set solver.method_choice.petsc_above=50";
  const CliOutcome a = run_cli(dir, "solve " + scene + " --out " + (dir / "auto").string(), env);
  ASSERT_EQ(a.code, 0) << a.err;
  const json choice = json::parse(slurp(dir / "auto" / "report.json")).at("engine_choice");
  EXPECT_EQ(choice.at("engine"), "cholmod");
  EXPECT_NE(choice.at("reason").get<std::string>().find((dir / "nowhere").string() + " is not there"), std::string::npos)
      << choice.dump();
  for (const std::string command : {"solve", "converge"}) {
    const CliOutcome g = run_cli(dir,
                                 command + " " + scene + " --set solver.engine='\"petsc\"' --out " +
                                     (dir / ("given-" + command)).string() + (command == "converge" ? " --levels 2 --reference 2" : ""),
                                 env);
    EXPECT_EQ(g.code, 2) << command << ": " << g.err;
    EXPECT_NE(g.err.find("is not there (build the target hemicontact_mpi"), std::string::npos) << command << ": " << g.err;
  }
  fs::remove_all(dir);
}

// The adaptive loop's levels take the petsc engine where the factorization predicted from the
// previous level's does not fit solver.method_choice.memory_fraction of the memory (lowered to
// 1e-6 here: every level after the first); the loop's meshes, estimates and energies must be those
// of the run that stays in this process, to the engines' agreement (file comment).
TEST(PetscEngine, AdaptiveLevelsTakeThePetscEngineWhereTheFactorizationWouldNotFit) {
  const fs::path dir = scratch("adapt-levels");
  const std::string scene = "solve " + problem("sofonea2017-3d") +
                            " --set output.vtu=false --set output.plot=false --set adapt.target_error=0.12 --out ";
  const CliOutcome here = run_cli(dir, scene + (dir / "here").string());
  ASSERT_EQ(here.code, 0) << here.err;
  const CliOutcome low = run_cli(dir, scene + (dir / "low").string() + " --set solver.method_choice.memory_fraction=1e-6");
  ASSERT_EQ(low.code, 0) << low.err;
  const json a = json::parse(slurp(dir / "here" / "report.json")).at("adapt").at("history");
  const json b = json::parse(slurp(dir / "low" / "report.json")).at("adapt").at("history");
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    SCOPED_TRACE("level " + std::to_string(k));
    EXPECT_EQ(a[k].at("dofs"), b[k].at("dofs"));
    EXPECT_NEAR(a[k].at("estimate").get<double>(), b[k].at("estimate").get<double>(), 1e-8);
    const double ea = a[k].at("energy").get<double>(), eb = b[k].at("energy").get<double>();
    EXPECT_LE(std::abs(ea - eb), 1e-8 * std::abs(ea));
    EXPECT_LE(b[k].at("certificate").get<double>(), 1e-8);
  }
  EXPECT_NE(a[1].at("method"), "petsc engine");
  EXPECT_EQ(b[1].at("method"), "petsc engine");
  EXPECT_NE(low.err.find("adapt: this level's engine petsc (auto): the factorization predicted"), std::string::npos)
      << low.err;
  // ssn there starts from the previous level's u, as a level solved here does.
  EXPECT_NE(low.err.find("ssn: from the caller's start (--start-follows)"), std::string::npos) << low.err;
  fs::remove_all(dir);
}

// ssn's start (--start-follows, studies/petsc_process.hpp): from the cholmod engine's answer, the
// petsc engine confirms it in one step (from zero: several), at the same answer; a start of the
// wrong size is refused naming both sizes.
TEST(PetscEngine, SsnFromTheCallersStartConfirmsTheAnswerAtOnce) {
  using namespace hemicontact;
  const nlohmann::json scene = load_scene(problem("sofonea2017-3d"), {"mesh.n=6"});
  const SolveOptions opt = solve_options_from_scene(scene);
  const Model md = build_model(scene, ".");
  const Solution ref = solve(md, opt);
  ASSERT_TRUE(ref.ok()) << ref.message;
  const PetscProcess engine(scene, ".");
  const Solution cold = engine(md, opt);
  const long cold_steps = engine.last_report().at("petsc").at("newton_iterations").get<long>();
  EXPECT_EQ(engine.last_report().at("petsc").at("start"), "zero");
  const Solution warm = engine(md, opt, &ref.u);
  const long warm_steps = engine.last_report().at("petsc").at("newton_iterations").get<long>();
  EXPECT_EQ(engine.last_report().at("petsc").at("start"), "the caller's u (--start-follows)");
  ASSERT_TRUE(cold.ok() && warm.ok()) << cold.message << warm.message;
  EXPECT_LE(warm_steps, 1);
  EXPECT_GT(cold_steps, 3);
  EXPECT_NEAR(warm.energy, ref.energy, 1e-10 * std::abs(ref.energy));
  EXPECT_NEAR(cold.energy, ref.energy, 1e-10 * std::abs(ref.energy));
  const Vec half = ref.u.head(ref.u.size() / 2);
  try {
    engine(md, opt, &half);
    ADD_FAILURE() << "a start of the wrong size was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--start-follows: " + std::to_string(half.size()) + " values for a mesh of " +
                                         std::to_string(md.mesh.num_nodes()) + " nodes in 3D"),
              std::string::npos)
        << e.what();
  }
}

// Under --mesh-follows stdin holds the caller's mesh after the scene's line, as large as the
// caller's own: not capped at MAX_SCENE_BYTES (an adaptive level of 122k nodes is 17 MB with its
// start), while the scene's line itself still is. 17 MB of zeros after a scene: the mesh's bytes are
// judged (and refused), not their size.
TEST(PetscEngine, MeshFollowsIsNotCappedAtTheScenesSize) {
  const fs::path dir = scratch("stream-large");
  const std::string mpi = (fs::path(HEMICONTACT_CLI_PATH).parent_path() / "hemicontact-mpi").string();
  const std::string cmd = "cd '" + dir.string() + "' && { tr -d '\\n' <" + problem("sofonea2017-3d") +
                          "; echo; head -c 17000000 /dev/zero; } | " + mpi +
                          " solve - --stream --mesh-follows >o.bin 2>e.txt";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << cmd;
  EXPECT_EQ(WEXITSTATUS(status), 2) << cmd;
  const std::string err = slurp(dir / "e.txt");
  EXPECT_NE(err.find("the mesh's bytes"), std::string::npos) << err;
  EXPECT_EQ(err.find("MAX_SCENE_BYTES"), std::string::npos) << err;
  fs::remove_all(dir);
}

// --stream on two ranks gathers every owned node's u into the whole mesh's numbering: the same
// report line's counts and the same u as one rank, to the engines' agreement (file comment).
TEST(PetscEngine, StreamGathersTheWholeDisplacementFromEveryRank) {
  const fs::path dir = scratch("stream-ranks");
  const std::string mpi = (fs::path(HEMICONTACT_CLI_PATH).parent_path() / "hemicontact-mpi").string();
  const auto stream = [&](int np, const std::string& name) {
    const std::string cmd = "cd '" + dir.string() + "' && " + MPIRUN + " " + std::to_string(np) + " " + mpi +
                            " solve - --stream --quiet --set mesh.n=6 <" + problem("sofonea2017-3d") + " >" + name;
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const std::string all = slurp(dir / name);
    const size_t eol = all.find('\n');
    EXPECT_NE(eol, std::string::npos);
    std::vector<double> u((all.size() - eol - 1) / sizeof(double));
    std::memcpy(u.data(), all.data() + eol + 1, u.size() * sizeof(double));
    return std::make_pair(json::parse(all.substr(0, eol)), u);
  };
  const auto [r1, u1] = stream(1, "one.bin");
  const auto [r2, u2] = stream(2, "two.bin");
  EXPECT_EQ(r2.at("petsc").at("ranks"), 2);
  EXPECT_EQ(r1.at("status_counts"), r2.at("status_counts"));
  ASSERT_EQ(u1.size(), 3u * 7 * 7 * 7);
  ASSERT_EQ(u2.size(), u1.size());
  double scale = 0, diff = 0;
  for (size_t i = 0; i < u1.size(); ++i) scale = std::max(scale, std::abs(u1[i])), diff = std::max(diff, std::abs(u1[i] - u2[i]));
  EXPECT_GT(scale, 0);
  EXPECT_LE(diff, 1e-8 * scale);
  fs::remove_all(dir);
}

// A 3D Gmsh mesh is sized by its file's header before anything is read (mesh/msh_peek.hpp): the
// plate (243 nodes, 729 unknowns) goes to the petsc engine above petsc_above and stays in the
// cholmod engine below it, each saying so with the count, and the answers agree.
TEST(PetscEngine, AutoSizesAGmshMeshByItsHeader) {
#if HEMICONTACT_HAS_GMSH
  const fs::path dir = scratch("engine-auto-gmsh");
  json scene = json::parse(slurp(problem("sofonea2017-3d")));
  scene["mesh"] = {{"type", "gmsh"}, {"file", HEMICONTACT_SOURCE_DIR "/tests/data/plate_2x2.msh"}};
  scene["boundary"] = {{"gamma1", json::array({json{{"physical", "clamped"}}})},
                       {"gamma3", json::array({json{{"physical", "contact"}}})}};
  std::ofstream(dir / "plate.json") << scene.dump(2);
  const std::string common = "solve " + (dir / "plate.json").string() + " --set output.vtu=false --quiet";
  const auto report = [&](const std::string& args, const std::string& name) {
    const CliOutcome r = run_cli(dir, common + args + " --out " + (dir / name).string());
    EXPECT_EQ(r.code, 0) << name << ": " << r.err;
    return json::parse(slurp(dir / name / "report.json"));
  };
  const json big = report(" --set solver.method_choice.petsc_above=700", "big");
  const json small = report(" --set solver.method_choice.petsc_above=730", "small");
  EXPECT_EQ(big.at("engine_choice").at("engine"), "petsc");
  EXPECT_EQ(small.at("engine_choice").at("engine"), "cholmod");
  for (const json* r : {&big, &small}) {
    EXPECT_NE(r->at("engine_choice").at("reason").get<std::string>().find("3D Gmsh mesh of 729 unknowns"),
              std::string::npos)
        << r->at("engine_choice").dump();
    EXPECT_TRUE(r->at("certificate").at("passed").get<bool>());
  }
  const double e = small.at("energy").get<double>();
  EXPECT_NEAR(big.at("energy").get<double>(), e, 1e-10 * std::abs(e));
  fs::remove_all(dir);
#else
  GTEST_SKIP() << "built without Gmsh";
#endif
}

// Every layout prints the summary (one function, output/report.hpp's summary_table): the pieces'
// from their reduced records and the Γ3 rows gathered to rank 0, the same lines as the cholmod
// engine's where the answers agree (statuses, counts, the certificate's verdict).
TEST(PetscEngine, ThePiecesPrintTheSameSummaryAsOneProcess) {
  const fs::path dir = scratch("slab-summary");
  const std::string args = "solve " + problem("sofonea2017-fig2") + " --set mesh.n=16 --set output.vtu=false";
  const CliOutcome one = run_cli(dir, args + " --out " + (dir / "one").string());
  const CliOutcome two = run_mpi(dir, 2, args + " --out " + (dir / "two").string());
  ASSERT_EQ(one.code, 0) << one.err;
  ASSERT_EQ(two.code, 0) << two.err;
  const auto line = [](const std::string& out, const std::string& label, int lines) {
    const size_t hit = out.compare(0, label.size(), label) == 0 ? 0 : out.find("\n" + label);
    if (hit == std::string::npos) return std::string("(no " + label + ")");
    const size_t at = hit == 0 ? 0 : hit + 1;
    size_t end = at;
    for (int i = 0; i < lines; ++i) end = out.find('\n', end) + 1;
    return out.substr(at, end - at);
  };
  EXPECT_NE(two.out.find("pieces)"), std::string::npos) << two.out;
  EXPECT_EQ(line(two.out, "status", 2), line(one.out, "status", 2)) << two.out;
  EXPECT_EQ(line(two.out, "gamma3 nodes", 4), line(one.out, "gamma3 nodes", 4)) << two.out;
  EXPECT_NE(line(two.out, "certificate", 1).find("passed"), std::string::npos) << two.out;
  EXPECT_NE(line(two.out, "mesh", 1).find("289 nodes, 512 cells, 17 gamma3 nodes"), std::string::npos) << two.out;
  fs::remove_all(dir);
}

// ssn runs in both engines (solver/ssn.hpp: the same node rows, CHOLMOD for CG + AMG): in the
// cholmod engine the summary names the engine's linear solve.
TEST(PetscEngine, SsnRunsInTheCholmodEngineToo) {
  const fs::path dir = scratch("ssn-cholmod");
  const CliOutcome r = run_cli(
      dir, "solve " + problem("sofonea2017-fig2") + " --set mesh.n=4 --backend ssn --out " + (dir / "o").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_OK) << r.err;
  EXPECT_NE(r.out.find("ssn (semismooth Newton, CHOLMOD)"), std::string::npos) << r.out;
  fs::remove_all(dir);
}

// Random scene 152 (studies/random_scenes.hpp): plain ssn's statuses cycled there for ever, in
// this engine too (certificate 1.04 after 60 steps). Its globalization (solver/ssn.hpp: a line
// search and the coupling column once a status signature comes back, summed over the ranks)
// certifies it on 1 and 2 ranks at the cholmod engine's answer, and the name says GMRES ran.
TEST(PetscEngine, SsnCertifiesTheRandomSceneWhoseStatusesCycled) {
  const fs::path dir = scratch("ssn-cycle");
  std::string args = "solve " + problem("sofonea2017-fig2") + " --quiet --set output.vtu=false";
  for (const auto& o : hemicontact::stress::draw_default_scene(152, 8, 16).overrides) args += " --set '" + o + "'";
  const CliOutcome c = run_cli(dir, args + " --set solver.engine='\"cholmod\"' --out " + (dir / "c").string());
  ASSERT_EQ(c.code, 0) << c.err;
  const json cholmod = json::parse(slurp(dir / "c" / "report.json"));
  for (const int np : {1, 2}) {
    const json r = solved(dir, np, args, "np" + std::to_string(np));
    if (HasFailure()) return;
    expect_same_answer(r, cholmod);
    EXPECT_NE(r.at("backend").at("name").get<std::string>().find("CG and GMRES"), std::string::npos) << r.at("backend");
  }
  fs::remove_all(dir);
}

TEST(PetscEngine, SsnStepCapExits3NamingTheKey) {
  const fs::path dir = scratch("ssn-cap");
  // fig2 at n = 16 needs 8 steps (statuses change in the first 5): 2 cannot finish.
  const CliOutcome r = run_mpi(dir, 2,
                               "solve " + problem("sofonea2017-fig2") +
                                   " --set mesh.n=16 --set solver.ssn.max_iters=2 --out " + (dir / "o").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_NOT_CONVERGED) << r.err;
  EXPECT_NE((r.err + r.out).find("solver.ssn.max_iters"), std::string::npos) << r.err << r.out;
  fs::remove_all(dir);
}

// ssn's two stops: the residual test (solver.ssn.tol) ends the default run as soon as an iterate keeps the
// statuses with a residual at round-off; with solver.ssn.tol below any reachable residual the step test
// (the Newton step stops decreasing at round-off) must end it, later, at the same answer.
TEST(PetscEngine, SsnStopsAtSsnTolOrWhereTheStepReachesRoundOff) {
  const fs::path dir = scratch("ssn-tol");
  const std::string common = "solve " + problem("sofonea2017-3d") + " --set mesh.n=8 --quiet --set output.vtu=false";
  const auto [ra, rb] = same_answer_twice(dir, 1, common, "--set solver.ssn.tol=1e-300");
  if (HasFatalFailure()) return;
  EXPECT_LT(ra.at("petsc").at("newton_iterations").get<long>(), rb.at("petsc").at("newton_iterations").get<long>());
  fs::remove_all(dir);
}

// DMPlex's parts (PT-Scotch) are the same from run to run, and so is every Krylov count that
// follows from them: one Scotch thread per rank and a fixed seed (petsc_plex_distribution.cpp).
// Threaded and clock-seeded, Debian's Scotch gave different parts from run to run. Crossed cells
// send fig2 to DMPlex; 3 ranks, so that the parts are not a bisection.
TEST(PetscEngine, DMPlexPartsAreTheSameFromRunToRun) {
  const fs::path dir = scratch("partition");
  const std::string common = "solve " + problem("sofonea2017-fig2") +
                             " --set mesh.n=16 --set mesh.diagonal='\"crossed\"' --quiet --set output.vtu=false";
  const json ra = solved(dir, 3, common, "a");
  const json rb = solved(dir, 3, common, "b");
  ASSERT_TRUE(ra.contains("petsc") && rb.contains("petsc"));
  expect_same_answer(ra, rb);
  const json& pa = ra.at("petsc").at("partition");
  EXPECT_EQ(pa.at("type"), "dmplex");
  long rows = 0;
  for (const auto& v : pa.at("rows_per_rank")) {
    EXPECT_GT(v.get<long>(), 0);
    rows += v.get<long>();
  }
  EXPECT_EQ(rows, ra.at("petsc").at("unknowns").get<long>());
  EXPECT_EQ(rb.at("petsc").at("partition"), pa);
  ASSERT_EQ(rb.at("petsc").at("minimizations").size(), ra.at("petsc").at("minimizations").size());
  for (size_t k = 0; k < ra.at("petsc").at("minimizations").size(); ++k)
    EXPECT_EQ(rb.at("petsc").at("minimizations")[k].at("krylov"), ra.at("petsc").at("minimizations")[k].at("krylov"))
        << "step " << k + 1;
  fs::remove_all(dir);
}

// ssn's hierarchy reuse: the reference a later step is judged against is the larger of the build
// step's CG iterations per decade and the first reuse step's (the first step, every Γ3 node fixed,
// is an easier matrix than any later one). So even with pc_rebuild = 1 (rebuild at any rise above
// the reference) the step after the first reuse is never a build: builds are at least 3 steps
// apart. On the 3D scene at n = 8 the old rule (the build step alone) rebuilt at step 3 (step 2:
// 13 CG iterations against 7). The answer does not depend on it.
TEST(PetscEngine, SsnJudgesTheHierarchyAgainstItsFirstReuse) {
  const fs::path dir = scratch("rebuild");
  const std::string common = "solve " + problem("sofonea2017-3d") + " --set mesh.n=8 --quiet --set output.vtu=false";
  const auto [ra, rb] = same_answer_twice(dir, 1, common, "--set solver.petsc.pc_rebuild=1");
  if (HasFatalFailure()) return;
  for (const json* r : {&ra, &rb}) {
    const json& steps = r->at("petsc").at("minimizations");
    ASSERT_GE(steps.size(), 3u);
    EXPECT_TRUE(steps[0].at("pc_built").get<bool>());
    int last = 1;
    for (const auto& st : steps) {
      if (!st.at("pc_built").get<bool>() || st.at("step").get<int>() == 1) continue;
      EXPECT_GE(st.at("step").get<int>() - last, 3) << "a build right after the reference step";
      last = st.at("step").get<int>();
    }
  }
  fs::remove_all(dir);
}

TEST(PetscEngine, TaoBackendInTheCholmodEngineNamesTheEngine) {
  const fs::path dir = scratch("tao-cholmod");
  const CliOutcome r =
      run_cli(dir, "solve " + problem("sofonea2017-fig2") + " --set mesh.n=4 --backend tao:bnls --out " +
                       (dir / "o").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_NE(r.err.find("solver.engine"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

// A backend of the cholmod engine that is named is refused, not silently replaced by ssn: ipopt
// (which the petsc engine once ran as ssn) as well as newton; solver.backend = auto means ssn.
TEST(PetscEngine, NonTaoBackendIsRefused) {
  for (const std::string b : {"newton", "ipopt"}) {
    SCOPED_TRACE(b);
    const fs::path dir = scratch(b);
    const CliOutcome r =
        run_mpi(dir, 2, "solve " + problem("sofonea2017-fig2") + " --set mesh.n=4 --backend " + b + " --out " +
                            (dir / "o").string());
    EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
    EXPECT_NE(r.err.find("solver.backend = '" + b + "'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "o" / "report.json"));
    fs::remove_all(dir);
  }
}

TEST(PetscEngine, MoreRanksThanCellsIsRefused) {
  const fs::path dir = scratch("ranks");
  // A 1 × 1 rectangle split along one diagonal has 2 triangles: 3 ranks are one too many (no Γ2:
  // the fig2 tractions act on upper halves that a single cell does not resolve).
  const CliOutcome r = run_mpi(dir, 3,
                               "solve " + problem("sofonea2017-fig2") +
                                   " --set mesh.n=1 --set mesh.diagonal='\"right\"' --set 'boundary.gamma2=[]' --out " +
                                   (dir / "o").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_NE(r.err.find("3 MPI ranks for a mesh of 2 cells"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

// An error on one rank while the others wait in a collective hung the job: rank 0
// printed "a rank's piece of the mesh has no free node" and waited in PetscFinalize, ranks 1 and 2
// spun in MPI_Allreduce. Every case must end every rank within seconds, with the message once and
// the documented exit code (mpirun exits with the code given to MPI_Abort). Under `timeout`: a
// hang is a failure (exit 124), not a stuck test.
TEST(PetscEngine, AnErrorOnOneRankEndsEveryRank) {
  const fs::path dir = scratch("one-rank-error");
  std::string mpirun = MPIRUN;
  mpirun.replace(mpirun.find("mpirun"), 6, "timeout -k 5 60 mpirun");
  struct Case {
    int np;
    std::string args;
  };
  const std::vector<Case> cases{
      {3, problem("sofonea2017-3d") + " --set mesh.n=2"},
      {2, problem("sofonea2017-fig2") +
              " --set mesh.n=2 --set 'boundary.gamma1=[{\"side\": \"left\"}]' --set 'boundary.gamma2=[]'"},
      {2, problem("sofonea2017-3d") + " --set mesh.n=2 --set 'boundary.gamma1=[{\"side\": \"front\"}]'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const auto t0 = std::chrono::steady_clock::now();
    const CliOutcome r = run_cli(dir, "solve " + c.args + " --set solver.engine='\"petsc\"' --quiet --out " +
                                          (dir / "o").string(),
                                 mpirun + " " + std::to_string(c.np));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
    const std::string message = "a rank's piece of the mesh has no free node";
    const size_t at = r.err.find(message);
    ASSERT_NE(at, std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(message, at + 1), std::string::npos) << "printed more than once:\n" << r.err;
    // Start-up, the failure and the abort: far below the hang's 60 s (10 s after the failure).
    EXPECT_LT(seconds, 30) << r.err;
    EXPECT_FALSE(fs::exists(dir / "o" / "report.json"));
  }
  // Two ranks of four failing alike (a Γ3 ending inside the blocks' ghost layer: ranks 1 and 3 met
  // an internal error and left without a word, ranks 0 and 2 hung). Whatever the engine makes of
  // the scene, a certified answer or an error, every rank ends, and an error is printed once.
  const std::string blocks = problem("sofonea2017-3d") +
                             " --set mesh.n=null --set mesh.nx=4 --set mesh.ny=2 --set mesh.nz=2 --set "
                             "solver.petsc.mesh='\"blocks\"' --set 'boundary.gamma3=[{\"side\": \"bottom\", "
                             "\"from\": 0, \"to\": 0.25}]'";
  const auto t0 = std::chrono::steady_clock::now();
  const CliOutcome r = run_cli(dir, "solve " + blocks + " --set solver.engine='\"petsc\"' --quiet --force --out " +
                                        (dir / "blocks").string(),
                               mpirun + " 4");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 30) << r.err;
  EXPECT_NE(r.code, 124) << "hung:\n" << r.err;
  if (r.code != 0) {
    const size_t at = r.err.find("hemicontact: error");
    ASSERT_NE(at, std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("hemicontact: error", at + 1), std::string::npos) << "printed more than once:\n" << r.err;
  }
  fs::remove_all(dir);
}

// Memory running out on one rank only (ulimit -v on rank 1) hung the job without a word: OpenBLAS
// retried a buffer it could not map for ever inside PETSc's GAMG, while rank 0 waited in a
// collective. Swept over limits that stop rank 1 at start-up (the OpenBLAS buffer), while its
// mesh is made (std::bad_alloc), at the assembly or in the solve (PETSc's allocator): each run
// must end every rank under `timeout` with exit code 2 and the memory message once, naming rank
// 1, or solve. Open MPI's own start-up may fail below some limit (its message, exit 1): allowed,
// not counted.
TEST(PetscEngine, MemoryRunningOutOnOneRankEndsEveryRank) {
  const fs::path dir = scratch("one-rank-memory");
  std::string mpirun = MPIRUN;
  mpirun.replace(mpirun.find("mpirun"), 6, "timeout -k 5 60 mpirun");
  int memory_errors = 0, solved = 0;
  std::vector<std::string> where;
  for (int mb = 280; mb <= 640; mb += 60) {
    SCOPED_TRACE("ulimit -v on rank 1: " + std::to_string(mb) + " MB");
    // bash runs the program as "$0" "$@" with rank 1's limit set; the CLI execs hemicontact-mpi.
    const std::string limited = mpirun + " 2 bash -c 'if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then ulimit -v " +
                                std::to_string(mb * 1024) + "; fi; exec \"$0\" \"$@\"'";
    const CliOutcome r = run_cli(dir, "solve " + problem("sofonea2017-3d") +
                                          " --set mesh.n=32 --set solver.engine='\"petsc\"' --quiet --force --out " +
                                          (dir / "o").string(),
                                 limited);
    ASSERT_NE(r.code, 124) << "hung:\n" << r.err;
    if (r.code == 0) {
      ++solved;
      continue;
    }
    if (r.code == 1 && r.err.find("hemicontact") == std::string::npos) continue;  // mpirun's start-up
    EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
    const std::string message = "hemicontact: error (rank 1): out of memory in ";
    const size_t at = r.err.find(message);
    ASSERT_NE(at, std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("out of memory", at + message.size()), std::string::npos) << "printed twice:\n" << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "o" / "report.json"));
    where.push_back(r.err.substr(at + message.size(), 40));
    ++memory_errors;
  }
  std::string seen;
  for (const std::string& w : where) seen += "\n  " + w;
  EXPECT_GE(memory_errors, 2) << seen;
  EXPECT_GE(solved, 1) << seen;
  fs::remove_all(dir);
}

TEST(PetscEngine, DivergedKrylovSolveExits3NamingTheReason) {
  const fs::path dir = scratch("ksp");
  // One CG iteration cannot reduce the residual by 1e-2 on this mesh: ssn's first Newton step
  // stops at the cap, KSP_DIVERGED_ITS, and the run says so with exit code 3 (not converged).
  const CliOutcome r =
      run_mpi(dir, 2, "solve " + problem("sofonea2017-fig2") + " --set mesh.n=16 --set solver.petsc.ksp_max_it=1 --out " +
                          (dir / "o").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_NOT_CONVERGED) << r.err;
  EXPECT_NE(r.err.find("DIVERGED_ITS"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("solver.petsc.ksp_max_it = 1"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

// A PETSc error from an option of the user's printed PETSc's traceback on every rank (or
// crashed); now it is one message naming PETSc's reason and solver.petsc.options, exit code 2. ILU
// is allowed (it works on one rank) but has no parallel implementation for MPIAIJ.
TEST(PetscEngine, PetscErrorFromAnOptionNamesTheOptions) {
  const fs::path dir = scratch("pcilu");
  const CliOutcome r =
      run_mpi(dir, 2, "solve " + problem("sofonea2017-fig2") + " --quiet --set mesh.n=8 "
                      "--set solver.petsc.options='\"-ssn_pc_type ilu\"' --out " + (dir / "o").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_NE(r.err.find("Could not locate a solver type for factorization type ILU"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("solver.petsc.options = '-ssn_pc_type ilu' is set"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("[0]PETSC ERROR"), std::string::npos) << r.err;  // no traceback
  EXPECT_FALSE(fs::exists(dir / "o" / "report.json"));
  fs::remove_all(dir);
}


// ---------------------------------------------------------------- the mesh made per rank (slabs)

// The rows of a Γ3 CSV (csv_writer.hpp) by column name.
std::vector<std::map<std::string, std::string>> csv_rows(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::vector<std::string> head;
  std::vector<std::map<std::string, std::string>> rows;
  const auto split = [](const std::string& l) {
    std::vector<std::string> out;
    std::stringstream ss(l);
    for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
    return out;
  };
  if (std::getline(in, line)) head = split(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line);
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < head.size() && i < cells.size(); ++i) row[head[i]] = cells[i];
    rows.push_back(std::move(row));
  }
  return rows;
}

// A Γ3 node's place, rounded to the mesh's grid (a key both engines' CSVs share).
std::string place(const std::map<std::string, std::string>& row) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.9f %.9f %.9f", std::stod(row.at("x")), std::stod(row.at("y")),
                row.count("z") ? std::stod(row.at("z")) : 0.0);
  return buf;
}

// The Γ3 rows of every piece the report lists, by place: each rank writes its owned nodes only, so
// every node must be in exactly one piece.
std::map<std::string, std::map<std::string, std::string>> piece_rows(const fs::path& out, const json& report) {
  std::map<std::string, std::map<std::string, std::string>> all;
  for (const auto& f : report.at("pieces").at("gamma3_csv"))
    for (auto& row : csv_rows(out / f.get<std::string>())) {
      const std::string key = place(row);
      EXPECT_EQ(all.count(key), 0u) << key << " is in two pieces (" << f << ")";
      all[key] = row;
    }
  return all;
}

// report.json's "nodes" of the slabs against the cholmod engine's: the same nodes (the whole mesh's
// numbers, the same order, the same places and weights), the same statuses; displacements within
// check.certificate_tol of max|u| and tractions within it of the certificate's traction scale S
// (each answer satisfies the unsmoothed conditions to tol in those units, on the same statuses).
// @return the largest relative differences {displacement, traction}.
std::pair<double, double> expect_same_nodes(const json& a, const json& b) {
  const json& na = a.at("nodes");
  const json& nb = b.at("nodes");
  EXPECT_EQ(na.size(), nb.size());
  if (na.size() != nb.size()) return {INFINITY, INFINITY};
  const double tol = b.at("options").at("certificate_tol").get<double>();
  const double S = a.at("certificate").at("traction_scale").get<double>();
  double U = 0, du = 0, ds = 0;
  for (size_t k = 0; k < na.size(); ++k) {
    EXPECT_EQ(na[k].size(), nb[k].size()) << "node " << k << ": the same keys";
    EXPECT_EQ(na[k].at("node"), nb[k].at("node")) << "node " << k;
    EXPECT_EQ(na[k].at("status"), nb[k].at("status")) << "node " << k;
    for (const char* key : {"x", "y", "z"}) {
      if (na[k].contains(key)) {
        EXPECT_EQ(na[k].at(key), nb[k].at(key)) << "node " << k << " " << key;
      }
    }
    for (const char* key : {"w", "g"}) {
      if (!na[k].at(key).is_null()) {
        EXPECT_NEAR(na[k].at(key).get<double>(), nb[k].at(key).get<double>(), 1e-13 * std::abs(na[k].at(key).get<double>()))
            << "node " << k << " " << key;
      }
    }
    EXPECT_EQ(na[k].contains("slip_dir") && na[k].at("slip_dir").is_null(),
              nb[k].contains("slip_dir") && nb[k].at("slip_dir").is_null());
    for (const char* key : {"u_nu", "u_tau"}) {
      U = std::max(U, std::abs(na[k].at(key).get<double>()));
      du = std::max(du, std::abs(na[k].at(key).get<double>() - nb[k].at(key).get<double>()));
    }
    for (const char* key : {"sigma_nu", "sigma_tau", "xi", "lambda"})
      ds = std::max(ds, std::abs(na[k].at(key).get<double>() - nb[k].at(key).get<double>()));
  }
  EXPECT_GT(U, 0);
  EXPECT_LE(du / U, tol) << "max |u_slabs - u_cholmod| / max |u| over report.json's nodes";
  EXPECT_LE(ds / S, tol) << "max |sigma_slabs - sigma_cholmod| / S over report.json's nodes";
  return {du / U, ds / S};
}

// A distributed run's report @p b against the cholmod engine's @p a: the certificate passed at
// check.certificate_tol, the same counts (statuses, nodes, Γ3 nodes, unknowns) and the energy and
// its terms within that tolerance of the energy's size (both pass the certificate at it).
void expect_same_report_scalars(const json& a, const json& b) {
  const double tol = b.at("options").at("certificate_tol").get<double>();
  EXPECT_TRUE(b.at("certificate").at("passed").get<bool>());
  EXPECT_LE(b.at("certificate").at("max_residual").get<double>(), tol);
  EXPECT_EQ(a.at("status_counts"), b.at("status_counts"));
  EXPECT_EQ(a.at("mesh").at("nodes"), b.at("mesh").at("nodes"));
  EXPECT_EQ(a.at("mesh").at("gamma3_nodes"), b.at("mesh").at("gamma3_nodes"));
  EXPECT_EQ(a.at("dofs"), b.at("dofs"));
  for (const char* key : {"energy", "energy_norm", "a_uu", "f_u", "j_term", "friction_term"}) {
    const double ea = a.at(key).get<double>(), eb = b.at(key).get<double>();
    EXPECT_LE(std::abs(ea - eb), tol * std::max(std::abs(a.at("energy").get<double>()), std::abs(ea))) << key;
  }
}

// Γ3 node by node from the pieces' CSVs (@p got) against the cholmod engine's gamma3.csv (@p ref):
// every node in one piece, with the whole list's index, node number and status.
// @return max |Δu_ν|, |Δu_τ| over max |u_ν|, |u_τ|.
double expect_same_piece_rows(const std::vector<std::map<std::string, std::string>>& ref,
                              const std::map<std::string, std::map<std::string, std::string>>& got) {
  EXPECT_EQ(ref.size(), got.size());
  double scale = 0, diff = 0;
  for (const auto& r : ref) {
    if (!got.count(place(r))) {
      ADD_FAILURE() << "no piece holds " << place(r);
      continue;
    }
    const auto& g = got.at(place(r));
    EXPECT_EQ(r.at("status"), g.at("status")) << place(r);
    EXPECT_EQ(r.at("index"), g.at("index")) << place(r);
    EXPECT_EQ(r.at("node"), g.at("node")) << place(r);
    for (const char* key : {"u_nu", "u_tau"}) {
      scale = std::max(scale, std::abs(std::stod(r.at(key))));
      diff = std::max(diff, std::abs(std::stod(r.at(key)) - std::stod(g.at(key))));
    }
  }
  EXPECT_GT(scale, 0);
  return scale > 0 ? diff / scale : INFINITY;
}

// The engine's record in report @p b of case @p c: ranks and method as asked, Newton and Krylov
// counts present and positive; the requested backend (auto = ssn) ran, and did the work.
void expect_engine_record(const json& b, const Case& c) {
  EXPECT_EQ(b.at("engine"), "petsc");
  EXPECT_EQ(b.at("petsc").at("ranks").get<int>(), c.np);
  EXPECT_EQ(b.at("petsc").at("method"), c.backend.empty() ? "ssn" : c.backend);
  EXPECT_GT(b.at("petsc").at("newton_iterations").get<long>(), 0);
  EXPECT_GT(b.at("petsc").at("krylov_iterations").get<long>(), 0);
  EXPECT_EQ(b.at("backend").at("requested"), c.backend.empty() ? "auto" : c.backend);
  EXPECT_EQ(b.at("backend").at("ran"), true);
  EXPECT_GT(b.at("backend").at("iterations").get<long>(), 0);
}

class PetscSlabs : public ::testing::TestWithParam<Case> {};

// Round-off for a polished answer on these meshes: the status system's conditioning (~1e4, the
// header's derivation) times machine precision gives ~1e-12; the polish's Newton stops when its
// step reaches 1e-14 of max|x|. An order of magnitude of slack over that.
constexpr double kRoundOff = 1e-11;

// The slabs against the cholmod engine: same statuses node by node, Γ3 displacements and energies
// within check.certificate_tol (both answers pass the certificate at that tolerance, and the
// status system's conditioning on these meshes, ~1e4, times ssn's stop at solver.ssn.tol = 1e-12 of
// max|f| stays below it); every rank holds about 1/P of the nodes. The runs leave
// solver.petsc.mesh at its default: a generated mesh takes the slabs (ssn, and TAO).
TEST_P(PetscSlabs, SameAnswerAsCholmodWithoutTheWholeMesh) {
  const Case& c = GetParam();
  const fs::path dir = scratch("slabs-" + c.scene + "-" + std::to_string(c.np));
  const std::string common = problem(c.scene) + " " + c.sets + " --quiet";
  // The reference is the cholmod engine by name: from 10 000 unknowns in 3D (n = 16) the default
  // engine, auto, would run the petsc engine in one process.
  const CliOutcome ref = run_cli(dir, "solve " + common + " --set solver.engine='\"cholmod\"' --set output.vtu=false --out " +
                                          (dir / "cholmod").string());
  ASSERT_EQ(ref.code, 0) << ref.err;
  const CliOutcome got = run_mpi(dir, c.np, "solve " + common + " --out " + (dir / "petsc").string() +
                                                  (c.backend.empty() ? "" : " --backend " + c.backend));
  ASSERT_EQ(got.code, 0) << got.err << got.out;
  const json a = json::parse(slurp(dir / "cholmod" / "report.json"));
  const json b = json::parse(slurp(dir / "petsc" / "report.json"));
  const bool blocks = c.layout == "blocks";
  ASSERT_EQ(b.at("petsc").at("partition").at("type"), c.layout);
  if (!blocks) {
    ASSERT_EQ(b.at("petsc").at("mesh"), "distributed (per-rank slabs)");
  }
  expect_engine_record(b, c);
  const double tol = b.at("options").at("certificate_tol").get<double>();
  expect_same_report_scalars(a, b);
  // report.json's nodes, gathered from the ranks, against the cholmod engine's list.
  const auto [du_nodes, ds_nodes] = expect_same_nodes(a, b);
  // Γ3, node by node, from the pieces against the cholmod engine's gamma3.csv.
  const double du_pieces =
      expect_same_piece_rows(csv_rows(dir / "cholmod" / "gamma3.csv"), piece_rows(dir / "petsc", b));
  EXPECT_LE(du_pieces, tol) << "max |u_slabs - u_cholmod| / max |u| on Gamma3";
  // No rank holds the whole mesh: at most its share of the layers plus two layers of ghosts (slabs),
  // or its share of the cell columns plus two node columns in x and in y (blocks).
  const json& m = b.at("scene").at("mesh");
  const bool box = m.at("type") == "box";
  const long layers = m.at(box ? "ny" : "nx").get<long>();
  const long layer_nodes = box ? (m.at("nx").get<long>() + 1) * (m.at("nz").get<long>() + 1) : m.at("ny").get<long>() + 1;
  const long local = b.at("petsc").at("local_nodes").get<long>();
  if (blocks) {
    const json& grid = b.at("petsc").at("blocks").at("grid");
    const long px = grid.at(0).get<long>(), py = grid.at(1).get<long>(), nx = m.at("nx").get<long>();
    EXPECT_EQ(px * py, c.np);
    EXPECT_EQ(b.at("petsc").at("mesh"), "distributed (per-rank blocks, " + std::to_string(px) + " x " + std::to_string(py) + ")");
    EXPECT_LE(local, ((nx + px - 1) / px + 2) * ((layers + py - 1) / py + 2) * (m.at("nz").get<long>() + 1));
  } else {
    EXPECT_LE(local, ((layers + c.np - 1) / c.np + 2) * layer_nodes);
  }
  if (c.np > 1 && !blocks) {
    EXPECT_LT(local, b.at("mesh").at("nodes").get<long>());
    // Every ghost got its owner's rows (the engine checks each row is in its owner's range, and the
    // owner's coordinates): each cut has a node layer of ghosts on either side.
    EXPECT_EQ(b.at("petsc").at("ghost_nodes").get<long>(), 2 * (c.np - 1) * layer_nodes);
    EXPECT_EQ(b.at("petsc").at("ghost_nodes_given_rows"), b.at("petsc").at("ghost_nodes"));
  }
  if (c.np > 1 && blocks) {
    EXPECT_LT(local, b.at("mesh").at("nodes").get<long>());
    EXPECT_GT(b.at("petsc").at("ghost_nodes").get<long>(), 0);
    EXPECT_EQ(b.at("petsc").at("ghost_nodes_given_rows"), b.at("petsc").at("ghost_nodes"));
  }
  // The parallel VTU: one piece per rank, each there and listed in the folder's files.
  const std::string pvtu = slurp(dir / "petsc" / "solution.pvtu");
  std::vector<std::string> files = b.at("files").get<std::vector<std::string>>();
  int pieces = 0;
  for (size_t at = pvtu.find("<Piece Source=\""); at != std::string::npos; at = pvtu.find("<Piece Source=\"", at + 1)) {
    const size_t q = at + 15;
    const std::string f = pvtu.substr(q, pvtu.find('"', q) - q);
    EXPECT_TRUE(fs::is_regular_file(dir / "petsc" / f)) << f;
    EXPECT_NE(std::find(files.begin(), files.end(), f), files.end()) << f;
    // Every array the .pvtu names is in the piece.
    const std::string piece = slurp(dir / "petsc" / f);
    for (size_t p = pvtu.find("<PDataArray"); p != std::string::npos; p = pvtu.find("<PDataArray", p + 1)) {
      const size_t n0 = pvtu.find("Name=\"", p) + 6;
      EXPECT_NE(piece.find("Name=\"" + pvtu.substr(n0, pvtu.find('"', n0) - n0) + "\""), std::string::npos);
    }
    ++pieces;
  }
  EXPECT_EQ(pieces, c.np);
  EXPECT_NE(pvtu.find("status_normal: -1 not on Gamma3"), std::string::npos) << "the status legend";
  // The records of what ran, as the cholmod engine has them (ssn: no polish, no outer loop).
  for (const char* key : {"solved_by", "phases", "fixed_point", "polish", "inner", "inner_convexity", "smallness"})
    EXPECT_TRUE(b.contains(key)) << key;
  const bool tao = c.backend.rfind("tao:", 0) == 0;
  EXPECT_EQ(b.at("polish").at("attempted"), tao);
  EXPECT_EQ(b.at("phases").size(), a.at("phases").size());
  for (const auto& line : b.at("skipped"))
    EXPECT_EQ(line.get<std::string>().rfind("polish: not on the distributed", 0), std::string::npos) << line;
  if (tao) {
    // TAO ends with the polish on the pieces too (the statuses fixed, the rule reduced over the
    // ranks): accepted, and the answer is then the status system's to round-off, as the cholmod
    // engine's is: the certificate and the distance to the cholmod engine at the status system's
    // conditioning (~1e4 here) times machine precision, not at the last smoothing width's.
    EXPECT_EQ(b.at("polish").at("accepted"), true) << b.at("polish");
    EXPECT_LE(b.at("certificate").at("max_residual").get<double>(), kRoundOff);
    EXPECT_LE(du_pieces, kRoundOff) << "max |u_slabs - u_cholmod| / max |u| on Gamma3, polished";
    std::printf("[%s] %s np=%d %s: polish %s in %d (certificate %.2e -> %.2e)\n", c.layout.c_str(),
                c.scene.c_str(), c.np, c.backend.c_str(), b.at("polish").at("accepted").get<bool>() ? "accepted" : "rejected",
                b.at("polish").at("iterations").get<int>(), b.at("polish").at("certificate_before").get<double>(),
                b.at("polish").at("certificate_after").get<double>());
  }
  std::printf("[%s] %s np=%d: max|du|/max|u| on Gamma3 = %.2e (report nodes %.2e, tractions/S %.2e), "
              "certificate %.2e, local nodes %ld of %ld\n",
              c.layout.c_str(), c.scene.c_str(), c.np, du_pieces, du_nodes, ds_nodes, b.at("certificate").at("max_residual").get<double>(),
              local, b.at("mesh").at("nodes").get<long>());
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(PaperScenes, PetscSlabs,
                         ::testing::Values(Case{"sofonea2017-fig2", "--set mesh.n=16", 1},
                                           Case{"sofonea2017-fig2", "--set mesh.n=16", 2},
                                           Case{"sofonea2017-printed", "--set mesh.n=16", 1},
                                           Case{"sofonea2017-printed", "--set mesh.n=16", 2},
                                           Case{"sofonea2017-3d", "--set mesh.n=4", 1},
                                           Case{"sofonea2017-3d", "--set mesh.n=8", 1},
                                           Case{"sofonea2017-3d", "--set mesh.n=8", 2},
                                           // n = 16: slip reversals at the stick limit (the
                                           // projection and one-step stick hold of run_ssn)
                                           Case{"sofonea2017-3d", "--set mesh.n=16", 2},
                                           // GAMG with all six rigid-body modes (the default
                                           // near-null space is the translations)
                                           Case{"sofonea2017-3d", "--set mesh.n=8 --set solver.petsc.near_null_space='\"rigid\"'", 2},
                                           // rollers: blocks of one unknown
                                           Case{"sofonea2017-fig2-half", "--set mesh.n=16", 2},
                                           // TAO's continuation and fixed point on the slabs
                                           // (solver/outer_loop.hpp), then the polish there
                                           Case{"sofonea2017-fig2", "--set mesh.n=16", 2, "tao:bnls"},
                                           Case{"sofonea2017-3d", "--set mesh.n=8", 2, "tao:bntr"},
                                           Case{"sofonea2017-3d", "--set mesh.n=4", 2, "tao:bnls"},
                                           // GAMG on TAO's inactive-set Hessians, whose size
                                           // changes between Newton steps (a fresh GAMG each)
                                           Case{"sofonea2017-3d", "--set mesh.n=4 --set solver.petsc.newton_pc='\"gamg\"'", 2, "tao:bnls"},
                                           // blocks of cell columns (a 2 x 2 grid, asked for), and
                                           // by default beyond one rank per layer (6 ranks, 4
                                           // layers: 2 x 3), TAO on them too
                                           Case{"sofonea2017-3d", "--set mesh.n=8 --set solver.petsc.mesh='\"blocks\"'", 4, "", "blocks"},
                                           Case{"sofonea2017-3d", "--set mesh.n=4", 6, "", "blocks"},
                                           Case{"sofonea2017-3d", "--set mesh.n=8 --set solver.petsc.mesh='\"blocks\"'", 4, "tao:bntr", "blocks"},
                                           // Γ3 that ends on a rank's ghost layer (the ghost then
                                           // has no Γ3 facet of its own: its weight, frame and
                                           // unknowns are its owner's), or covers only some ranks;
                                           // each failed with an internal error before
                                           Case{"sofonea2017-fig2", "--set mesh.n=16 --set boundary.gamma3='[{\"side\":\"bottom\",\"from\":0,\"to\":0.4375}]'", 2},
                                           Case{"sofonea2017-fig2", "--set mesh.n=16 --set boundary.gamma3='[{\"side\":\"bottom\",\"from\":0.5,\"to\":1}]'", 3},
                                           // Γ1 that ends on a ghost layer: the ghost is clamped as its owner says
                                           Case{"sofonea2017-fig2", "--set mesh.n=16 --set boundary.gamma1='[{\"side\":\"top\",\"from\":0,\"to\":0.4375}]'", 2},
                                           Case{"sofonea2017-3d", "--set mesh.n=null --set mesh.nx=4 --set mesh.ny=4 --set mesh.nz=2 --set boundary.gamma3='[{\"side\":\"bottom\",\"from\":0,\"to\":0.25}]'", 3},
                                           Case{"sofonea2017-3d", "--set mesh.n=null --set mesh.nx=4 --set mesh.ny=2 --set mesh.nz=2 --set solver.petsc.mesh='\"blocks\"' --set boundary.gamma3='[{\"side\":\"bottom\",\"from\":0,\"to\":0.25}]'", 4, "", "blocks"}));

// A Gmsh file (mesh.file) on the petsc engine's default mesh: rank 0 reads it, DMPlex distributes it
// (docs/petsc-engine.md, "Distributed mesh"), and on 1, 2 and 3 ranks the answer is the cholmod
// engine's: the same statuses node by node, report.json's nodes named by the same whole-mesh
// numbers, Γ3 displacements and energies within check.certificate_tol (as PetscSlabs), the
// certificate passed; on 2 and 3 ranks no rank holds the whole mesh, and the ghosts got their
// owners' rows. The meshes: tests/data/strip_4x1.msh and plate_2x2.msh (make_strip_msh.py; node
// tags permuted, so that a wrong node number would show; thin, so that every part has Γ3 nodes).
TEST(PetscEngine, GmshMeshDistributedByDMPlex) {
#if HEMICONTACT_HAS_GMSH
  const fs::path dir = scratch("plex");
  // 2D: fig2's scene on the strip; 3D: the 3D scene on the plate (tests/data/plate_2x2.msh).
  for (const bool three_d : {false, true}) {
    SCOPED_TRACE(three_d ? "plate_2x2.msh" : "strip_4x1.msh");
    json scene = json::parse(slurp(problem(three_d ? "sofonea2017-3d" : "sofonea2017-fig2")));
    const std::string file = three_d ? "plate_2x2.msh" : "strip_4x1.msh";
    scene["mesh"] = {{"type", "gmsh"}, {"file", HEMICONTACT_SOURCE_DIR "/tests/data/" + file}};
    // Clamped on top, pushed on the sides' upper halves, in contact below (fig2's conditions).
    const double from = three_d ? 0.25 : 0.5, to = three_d ? 0.5 : 1.0;
    json push = three_d ? json::array({8000.0, 0.0, 0.0}) : json::array({8000.0, 0.0}), pull = push;
    pull[0] = -8000.0;
    scene["boundary"] = json::object();
    scene["boundary"]["gamma1"] = json::array({json{{"physical", "clamped"}}});
    scene["boundary"]["gamma2"] = json::array({json{{"side", "left"}, {"from", from}, {"to", to}, {"traction", push}},
                                               json{{"side", "right"}, {"from", from}, {"to", to}, {"traction", pull}}});
    scene["boundary"]["gamma3"] = json::array({json{{"physical", "contact"}}});
    const std::string name = three_d ? "plate" : "strip";
    std::ofstream(dir / (name + ".json")) << scene.dump(2);
    const std::string common = (dir / (name + ".json")).string() + " --quiet";
    const CliOutcome ref = run_cli(dir, "solve " + common + " --set output.vtu=false --out " + (dir / (name + "-cholmod")).string());
    ASSERT_EQ(ref.code, 0) << ref.err;
    const json a = json::parse(slurp(dir / (name + "-cholmod") / "report.json"));
    const auto ref_rows = csv_rows(dir / (name + "-cholmod") / "gamma3.csv");
    for (int np : {1, 2, 3}) {
      SCOPED_TRACE("np=" + std::to_string(np));
      const std::string out = name + "-petsc" + std::to_string(np);
      const CliOutcome got = run_mpi(dir, np, "solve " + common + " --out " + (dir / out).string());
      ASSERT_EQ(got.code, 0) << got.err << got.out;
      const json b = json::parse(slurp(dir / out / "report.json"));
      const std::string mesh = b.at("petsc").at("mesh").get<std::string>();
      EXPECT_EQ(mesh.rfind("distributed (DMPlex, ", 0), 0u) << mesh;
      EXPECT_EQ(b.at("petsc").at("partition").at("type"), "dmplex");
      const double tol = b.at("options").at("certificate_tol").get<double>();
      expect_same_report_scalars(a, b);
      EXPECT_EQ(a.at("mesh").at("cells"), b.at("mesh").at("cells"));
      const auto [du_nodes, ds_nodes] = expect_same_nodes(a, b);
      EXPECT_LE(expect_same_piece_rows(ref_rows, piece_rows(dir / out, b)), tol) << "max |du| / max |u| from the pieces";
      const long local = b.at("petsc").at("local_nodes").get<long>(), nodes = b.at("mesh").at("nodes").get<long>();
      if (np > 1) {
        EXPECT_LT(local, nodes) << "a rank holds the whole mesh";
        // Every ghost got its owner's rows (and was where its owner has it: the engine checks).
        EXPECT_GT(b.at("petsc").at("ghost_nodes").get<long>(), 0);
        EXPECT_EQ(b.at("petsc").at("ghost_nodes_given_rows"), b.at("petsc").at("ghost_nodes"));
      }
      std::printf("[dmplex] %s np=%d (%s): report nodes max|du|/max|u| %.2e, tractions/S %.2e, certificate %.2e, "
                  "local nodes %ld of %ld, ghosts %ld\n",
                  file.c_str(), np, mesh.c_str(), du_nodes, ds_nodes, b.at("certificate").at("max_residual").get<double>(),
                  local, nodes, b.at("petsc").at("ghost_nodes").get<long>());
    }
  }
  // Γ3 on the strip's left end only: the part DMPlex gives rank 1 holds none of it, and the run
  // stays distributed (the check that a contact law has Γ3 nodes is made over the ranks).
  const std::string quarter = (dir / "strip.json").string() + " --quiet --set output.vtu=false " +
                              "--set 'boundary.gamma3=[{\"side\":\"bottom\",\"from\":0,\"to\":0.5}]'";
  const CliOutcome qa = run_cli(dir, "solve " + quarter + " --out " + (dir / "quarter-cholmod").string());
  ASSERT_EQ(qa.code, 0) << qa.err;
  const json ra = json::parse(slurp(dir / "quarter-cholmod" / "report.json"));
  const json rb = solved(dir, 2, "solve " + quarter, "quarter-petsc");
  ASSERT_TRUE(rb.contains("petsc"));
  EXPECT_EQ(rb.at("petsc").at("mesh").get<std::string>().rfind("distributed (DMPlex, ", 0), 0u);
  EXPECT_TRUE(rb.at("certificate").at("passed").get<bool>());
  EXPECT_EQ(ra.at("status_counts"), rb.at("status_counts"));
  expect_same_nodes(ra, rb);
  fs::remove_all(dir);
#else
  GTEST_SKIP() << "built without Gmsh (read_gmsh reads the file on rank 0)";
#endif
}

// --plot on the slabs draws from the pieces (no whole VTU or CSV exists): fig2.png from the .pvtu's
// pieces, status3d.png from the rank CSVs, each listed in the report's files.
TEST(PetscEngine, PlotDrawsFromTheSlabPieces) {
  if (!matplotlib_available()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  const fs::path dir = scratch("slab-plot");
  for (const auto& [scene, picture] : {std::pair<std::string, std::string>{"sofonea2017-fig2", "fig2.png"},
                                       std::pair<std::string, std::string>{"sofonea2017-3d", "status3d.png"}}) {
    SCOPED_TRACE(scene);
    const json r = solved(dir, 2, "solve " + problem(scene) + " --set mesh.n=4 --quiet --plot", scene);
    ASSERT_TRUE(r.contains("petsc"));
    EXPECT_EQ(r.at("petsc").at("mesh"), "distributed (per-rank slabs)");
    EXPECT_FALSE(fs::exists(dir / scene / "solution.vtu"));
    EXPECT_TRUE(fs::is_regular_file(dir / scene / picture));
    EXPECT_GT(fs::file_size(dir / scene / picture), 1000u);
    const auto files = r.at("files").get<std::vector<std::string>>();
    EXPECT_NE(std::find(files.begin(), files.end(), picture), files.end());
  }
  fs::remove_all(dir);
}

// solver.petsc.mesh = "blocks" where no grid of blocks exists: a rectangle (blocks cut a box's
// columns; fig2's Γ3 would leave some without contact), 5 ranks on a 2 x 2-column box (5 is prime
// and above both), a perturbed box (its draws run over the whole box): an input error naming the
// key and why, from every rank alike, no result.
TEST(PetscEngine, BlocksRefuseWhatTheyCannotCut) {
  const fs::path dir = scratch("blocks-refused");
  const std::string blocks = " --set solver.petsc.mesh='\"blocks\"' --quiet --set output.vtu=false";
  const CliOutcome rect = run_mpi(dir, 2, "solve " + problem("sofonea2017-fig2") + " --set mesh.n=8" + blocks +
                                              " --out " + (dir / "rect").string());
  EXPECT_EQ(rect.code, hemicontact::EXIT_INPUT) << rect.err;
  EXPECT_NE(rect.err.find("solver.petsc.mesh = \"blocks\": only a generated box"), std::string::npos) << rect.err;
  EXPECT_FALSE(fs::exists(dir / "rect" / "report.json"));
  const CliOutcome five = run_mpi(dir, 5, "solve " + problem("sofonea2017-3d") + " --set mesh.n=2" + blocks +
                                              " --out " + (dir / "five").string());
  EXPECT_EQ(five.code, hemicontact::EXIT_INPUT) << five.err;
  EXPECT_NE(five.err.find("5 MPI ranks do not make a grid of blocks of the box's 2 x 2 cell columns"), std::string::npos)
      << five.err;
  EXPECT_FALSE(fs::exists(dir / "five" / "report.json"));
  // A perturbed box: asked for blocks, refused (auto would send it to DMPlex), naming mesh.perturb.
  const CliOutcome perturbed = run_mpi(dir, 2, "solve " + problem("sofonea2017-3d") + " --set mesh.n=4 --set mesh.perturb=0.1" +
                                                    blocks + " --out " + (dir / "perturbed").string());
  EXPECT_EQ(perturbed.code, hemicontact::EXIT_INPUT) << perturbed.err;
  EXPECT_NE(perturbed.err.find("mesh.perturb: a box made in blocks is not perturbed"), std::string::npos) << perturbed.err;
  EXPECT_FALSE(fs::exists(dir / "perturbed" / "report.json"));
  fs::remove_all(dir);
}

// The polish's second reading on the pieces: TAO ends at a smoothing width of 5 U
// (solver.eps_tau = eps_nu = eps_start = 5), where the polish on the statuses read at
// check.status_tol is rejected (polish_with_readings then reads them at 10 ε, which the note says)
// and the second is accepted. Its answer does not pass the certificate: exit 4 and report.json
// saying so. On 1 rank the acceptance rule reads every Γ3 node on the one piece; on 2 it is reduced
// over the ranks: the same polish record (note, iterations, before and after to the certificate's
// tolerance) and the same statuses.
TEST(PetscEngine, ThePolishsSecondReadingIsTheSameOnOneAndTwoRanks) {
  const fs::path dir = scratch("polish-readings");
  const std::string args = "solve " + problem("sofonea2017-fig2") +
                           " --set mesh.n=16 --backend tao:bnls --set solver.eps_tau=5 --set solver.eps_nu=5 "
                           "--set solver.continuation.eps_start=5 --set output.vtu=false --quiet";
  std::map<int, json> reports;
  for (const int np : {1, 2}) {
    const std::string name = "np" + std::to_string(np);
    const CliOutcome r = run_mpi(dir, np, args + " --out " + (dir / name).string());
    EXPECT_EQ(r.code, hemicontact::EXIT_CERTIFICATE) << name << ": " << r.err;
    ASSERT_TRUE(fs::exists(dir / name / "report.json")) << name;
    reports[np] = json::parse(slurp(dir / name / "report.json"));
    EXPECT_EQ(reports[np].at("petsc").at("mesh"), "distributed (per-rank slabs)") << name;
    const json& p = reports[np].at("polish");
    EXPECT_EQ(p.at("attempted"), true) << name;
    EXPECT_EQ(p.at("accepted"), true) << name;
    EXPECT_EQ(p.at("note"), "statuses read at 10 eps") << name;
    EXPECT_EQ(reports[np].at("certificate").at("passed"), false) << name;
    EXPECT_EQ(reports[np].at("ok"), false) << name;
  }
  const json &a = reports.at(2), &b = reports.at(1);
  EXPECT_EQ(a.at("status_counts"), b.at("status_counts"));
  EXPECT_EQ(a.at("polish").at("iterations"), b.at("polish").at("iterations"));
  const double rtol = a.at("options").at("certificate_tol").get<double>();
  for (const char* key : {"certificate_before", "certificate_after"}) {
    const double x = a.at("polish").at(key).get<double>(), y = b.at("polish").at(key).get<double>();
    EXPECT_LE(std::abs(x - y), rtol * std::abs(y)) << key;
  }
  fs::remove_all(dir);
}

// What the slabs do not cover (a perturbed mesh, crossed cells) is made on rank 0 and distributed
// by DMPlex with the default solver.petsc.mesh, with the cholmod engine's answer (TAO and ssn); a
// slab without Γ3 does not send the run elsewhere.
TEST(PetscEngine, WhatTheSlabsDoNotCoverIsDistributedByDMPlex) {
  const fs::path dir = scratch("not-slabs");
  for (const auto& [scene, sets, backend] :
       {std::tuple<std::string, std::string, std::string>{"sofonea2017-3d", "--set mesh.n=4 --set mesh.perturb=0.1", "tao:bnls"},
        std::tuple<std::string, std::string, std::string>{"sofonea2017-fig2", "--set mesh.n=8 --set mesh.diagonal='\"crossed\"'", "ssn"}}) {
    SCOPED_TRACE(scene + " " + sets);
    const std::string args = problem(scene) + " " + sets + " --quiet --set output.vtu=false";
    const CliOutcome ref = run_cli(dir, "solve " + args + " --out " + (dir / (scene + "-cholmod")).string());
    ASSERT_EQ(ref.code, 0) << ref.err;
    const json a = json::parse(slurp(dir / (scene + "-cholmod") / "report.json"));
    const json r = solved(dir, 2, "solve " + args + " --backend " + backend, scene);
    ASSERT_TRUE(r.contains("petsc"));
    EXPECT_EQ(r.at("petsc").at("mesh").get<std::string>().rfind("distributed (DMPlex, ", 0), 0u) << r.at("petsc").at("mesh");
    EXPECT_TRUE(r.at("certificate").at("passed").get<bool>());
    EXPECT_EQ(a.at("status_counts"), r.at("status_counts"));
    EXPECT_EQ(a.at("mesh").at("nodes"), r.at("mesh").at("nodes"));
    const auto [du, ds] = expect_same_nodes(a, r);
    if (backend != "ssn") {  // TAO on DMPlex's parts: polished there too (PetscSlabs)
      EXPECT_EQ(r.at("polish").at("accepted"), true) << r.at("polish");
      EXPECT_LE(r.at("certificate").at("max_residual").get<double>(), kRoundOff);
      EXPECT_LE(du, kRoundOff);
      std::printf("[dmplex] %s: polish in %d, certificate %.2e -> %.2e, u against cholmod %.2e, tractions/S %.2e\n",
                  scene.c_str(), r.at("polish").at("iterations").get<int>(),
                  r.at("polish").at("certificate_before").get<double>(),
                  r.at("polish").at("certificate_after").get<double>(), du, ds);
    }
  }
  // Γ3 on the left quarter of the bottom: the second slab (x >= 1/2) holds none of it, and the run
  // stays on the slabs (the check that a contact law has Γ3 nodes is made over the ranks), with the
  // cholmod engine's answer.
  const std::string quarter = problem("sofonea2017-fig2") + " --set mesh.n=16 --quiet --set output.vtu=false --set "
                              "'boundary.gamma3=[{\"side\":\"bottom\",\"from\":0,\"to\":0.25}]'";
  const CliOutcome qa = run_cli(dir, "solve " + quarter + " --out " + (dir / "quarter-cholmod").string());
  ASSERT_EQ(qa.code, 0) << qa.err;
  const json ra = json::parse(slurp(dir / "quarter-cholmod" / "report.json"));
  const json q = solved(dir, 2, "solve " + quarter, "quarter");
  ASSERT_TRUE(q.contains("petsc"));
  EXPECT_EQ(q.at("petsc").at("mesh"), "distributed (per-rank slabs)");
  EXPECT_TRUE(q.at("certificate").at("passed").get<bool>());
  EXPECT_EQ(ra.at("status_counts"), q.at("status_counts"));
  expect_same_nodes(ra, q);
  fs::remove_all(dir);
}

// The retired replicated layout: an input error from every rank alike, naming the key, the layouts
// that replace it and where to read why; no result.
TEST(PetscEngine, TheReplicatedLayoutIsRefusedNamingTheDistributedOnes) {
  const fs::path dir = scratch("replicated-refused");
  const CliOutcome r = run_mpi(dir, 2, "solve " + problem("sofonea2017-3d") +
                                           " --set mesh.n=4 --quiet --set solver.petsc.mesh='\"replicated\"' --out " +
                                           (dir / "o").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_NE(r.err.find("scene key 'solver.petsc.mesh': \"replicated\": the replicated layout of the petsc engine was "
                       "retired: the distributed layouts (slabs, blocks, DMPlex) solve every scene"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("docs/petsc-engine.md"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o" / "report.json"));
  fs::remove_all(dir);
}

#else

TEST(PetscEngine, EngineNotBuiltNamesThePackage) {
  const fs::path dir = scratch("absent");
  const CliOutcome r = run_cli(dir, "solve " + problem("sofonea2017-fig2") +
                                        " --set mesh.n=4 --set solver.engine='\"petsc\"' --out " + (dir / "o").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_NE(r.err.find("libpetsc-real-dev"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o" / "report.json"));
  fs::remove_all(dir);
}

#endif

}  // namespace
