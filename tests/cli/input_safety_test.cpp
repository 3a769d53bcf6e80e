// The inputs: what a careless or hostile input did to the program, end to end through
// the built `hemicontact`. Scene paths that are devices, FIFOs or huge files; memory limits (the
// estimate honours ulimit -v, Γ3 is in it, an allocation failure is a memory message with exit 2,
// never a crash); the default engine under mpirun; an adaptive target that is not met (exit 3,
// "ok": false) and an interrupted adaptive solve (its certified levels kept); converge's options
// bounded by the keys they set. The one-line refusals of single keys are in bad_input_test.cpp.
#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>

#include "support/cli_runner.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using json = nlohmann::json;
using hemicontact::test::slurp;

namespace {

const std::string FIG2 = HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json";

class InputSafety : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::temp_directory_path() / ("hemicontact_inputs_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  hemicontact::test::CliOutcome cli(const std::string& args, const std::string& env = "") const {
    return hemicontact::test::run_cli(dir, args, env);
  }
  bool has(const std::string& text, const std::string& part) const { return text.find(part) != std::string::npos; }
  fs::path dir;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

// /dev/zero was read for 18 s, /dev/urandom never ended, and a FIFO would block in open(): a scene
// path must be a regular file, and at most MAX_SCENE_BYTES are read.
TEST_F(InputSafety, SceneFileMustBeARegularFileOfBoundedSize) {
  const fs::path fifo = dir / "scene.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {std::string("/dev/zero"), std::string("/dev/urandom"), fifo.string()}) {
    SCOPED_TRACE(path);
    const auto t0 = std::chrono::steady_clock::now();
    // timeout: a regression must fail the test, not hang the suite.
    const auto r = cli("solve " + path + " --out " + (dir / "out").string(), "timeout 20");
    EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
    EXPECT_TRUE(has(r.err, "is not a regular file")) << r.err;
    EXPECT_LT(seconds_since(t0), 3.0);
  }
  // 17 MB of spaces around a valid scene: refused by its length, not parsed.
  const fs::path big = dir / "big.json";
  {
    std::ofstream out(big);
    out << slurp(FIG2);
    const std::string spaces(1 << 20, ' ');
    for (int i = 0; i < 17; ++i) out << spaces;
  }
  const auto r = cli("solve " + big.string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_TRUE(has(r.err, "is longer than 16 MB")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "report.json"));
}

// ulimit -v 800000 with n = 512 crashed (SIGSEGV in the condensation) after the estimate, which read
// the machine's free memory only, let it through. Now the address-space limit is the budget: the
// run is refused at once, naming the limit and the size key.
TEST_F(InputSafety, MemoryEstimateHonoursTheAddressSpaceLimit) {
#if defined(HEMICONTACT_SANITIZED)
  GTEST_SKIP() << "address-space limits (ulimit -v) cannot apply under AddressSanitizer: its shadow memory is reserved "
                  "address space";
#endif
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = cli("solve " + FIG2 + " --quiet --set mesh.n=512 --set output.vtu=false --out " + (dir / "out").string(),
                     "ulimit -v 800000;");
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_TRUE(has(r.err, "mesh.n = 512: a mesh of 2.63e+05 nodes needs about")) << r.err;
  EXPECT_TRUE(has(r.err, "the address-space limit (ulimit -v")) << r.err;
  EXPECT_LT(seconds_since(t0), 3.0);
}

// A 20000 x 1 strip is all Γ3: the condensation's dense Γ3 matrices (3 x 40 002² doubles, 38 GB)
// ended in bad_alloc (exit 5, "internal error"). Γ3 is in the estimate now; the limit makes the
// refusal independent of the machine's memory.
TEST_F(InputSafety, Gamma3IsInTheMemoryEstimate) {
#if defined(HEMICONTACT_SANITIZED)
  GTEST_SKIP() << "address-space limits (ulimit -v) cannot apply under AddressSanitizer: its shadow memory is reserved "
                  "address space";
#endif
  const auto r = cli("solve " + FIG2 + " --quiet --set mesh.n=null --set mesh.nx=20000 --set mesh.ny=1 --set boundary.gamma2=[] --out " +
                         (dir / "out").string(),
                     "ulimit -v 4000000;");
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_TRUE(has(r.err, "with 20001 Γ3 nodes (dense condensed Γ3 matrices")) << r.err;
  EXPECT_TRUE(has(r.err, "use fewer Γ3 nodes")) << r.err;
}

// Under address-space limits from "barely starts" upwards, a solve either succeeds or ends with a
// memory message and exit code 2: never a signal, a hang or "internal error" (at 336 MB it hung in
// OpenBLAS, whose buffer the budget now keeps room for; at 352 MB a thread that could not be
// created ended as "internal error"). OPENBLAS_NUM_THREADS=1: OpenBLAS's worker threads map their
// buffers when the library loads, before main, and retry for ever when that fails (docs/robustness.md).
TEST_F(InputSafety, AllocationFailuresUnderALimitEndWithAMemoryMessage) {
#if defined(HEMICONTACT_SANITIZED)
  GTEST_SKIP() << "address-space limits (ulimit -v) cannot apply under AddressSanitizer: its shadow memory is reserved "
                  "address space";
#endif
  const std::string blas = "OPENBLAS_NUM_THREADS=1";
  // The smallest limit (MB) under which the program runs at all (loading its libraries).
  int base = 0;
  for (int mb = 48; mb <= 4096 && base == 0; mb += 16)
    if (cli("backends", "ulimit -v " + std::to_string(mb * 1024) + "; " + blas).code == 0) base = mb;
  ASSERT_GT(base, 0) << "hemicontact did not start under 4 GB of address space";
  int memory_refusals = 0, successes = 0;
  for (int extra = 0; extra <= 480; extra += 48) {
    const std::string limit = std::to_string((base + extra) * 1024);
    SCOPED_TRACE("ulimit -v " + limit);
    const auto r = cli("solve " + FIG2 + " --quiet --force --set mesh.n=96 --set check.smallness=false --out " +
                           (dir / "out").string(),
                       "ulimit -v " + limit + "; " + blas + " timeout 20");
    if (r.code == hemicontact::EXIT_OK) {
      ++successes;
      continue;
    }
    EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
    EXPECT_TRUE(has(r.err, "out of memory in") || has(r.err, "are available: the address-space limit")) << r.err;
    EXPECT_FALSE(has(r.err, "internal error")) << r.err;
    ++memory_refusals;
  }
  EXPECT_GT(memory_refusals, 0);
  EXPECT_GT(successes, 0);
}

// Under mpirun the default engine ran once per rank, every rank racing for the same --out: refused
// with the hint to use the petsc engine, before the folder is touched.
TEST_F(InputSafety, DefaultEngineUnderMpirunIsRefusedWithTheHint) {
  for (const char* env : {"OMPI_COMM_WORLD_SIZE=2", "PMI_SIZE=4"}) {
    SCOPED_TRACE(env);
    const auto r = cli("solve " + FIG2 + " --set mesh.n=4 --out " + (dir / "out").string(), env);
    EXPECT_EQ(r.code, hemicontact::EXIT_USAGE) << r.err;
    EXPECT_TRUE(has(r.err, "MPI ranks") && has(r.err, "solver.engine='\"petsc\"'")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
  const auto one = cli("solve " + FIG2 + " --quiet --set mesh.n=4 --out " + (dir / "one").string(), "OMPI_COMM_WORLD_SIZE=1");
  EXPECT_EQ(one.code, hemicontact::EXIT_OK) << one.err;
  const auto c = cli("converge " + FIG2 + " --levels 2 --reference 4 --out " + (dir / "c").string(), "PMI_SIZE=2");
  EXPECT_EQ(c.code, hemicontact::EXIT_USAGE) << c.err;
}

// An adaptive solve stopped by a cap far above its target exited 0 with "ok": true. Now: exit 3,
// "ok": false and the reason naming the cap; the certified levels are in adapt_levels.json.
TEST_F(InputSafety, AdaptiveTargetNotMetIsNotOk) {
  const fs::path out = dir / "a";
  const auto r = cli("solve " + FIG2 + " --quiet --set mesh.n=8 --set adapt.target_error=0.001 --set adapt.max_levels=2 " +
                     "--set check.smallness=false --out " + out.string());
  EXPECT_EQ(r.code, hemicontact::EXIT_NOT_CONVERGED) << r.err;
  EXPECT_TRUE(has(r.err, "adapt.target_error = 0.001 not met: stopped by adapt.max_levels")) << r.err;
  const json rep = json::parse(slurp(out / "report.json"));
  EXPECT_FALSE(rep.at("ok").get<bool>());
  EXPECT_TRUE(rep.at("certificate").at("passed").get<bool>());  // the final mesh's answer itself is fine
  EXPECT_TRUE(has(rep.at("adapt").at("reason").get<std::string>(), "raise adapt.max_levels"));
  EXPECT_TRUE(has(rep.at("message").get<std::string>(), "not met"));
  const json levels = json::parse(slurp(out / "adapt_levels.json"));
  EXPECT_FALSE(levels.at("partial").get<bool>());  // the loop ended (interrupted: below)
  EXPECT_EQ(levels.at("history").size(), 2u);
  // Met: exit 0 and ok, as before.
  const auto met = cli("solve " + FIG2 + " --quiet --set mesh.n=8 --set adapt.target_error=0.1 " +
                       "--set check.smallness=false --out " + (dir / "b").string());
  EXPECT_EQ(met.code, hemicontact::EXIT_OK) << met.err;
  EXPECT_TRUE(json::parse(slurp(dir / "b" / "report.json")).at("ok").get<bool>());
}

// An interrupted adaptive solve kept none of its certified levels: adapt_levels.json is written
// after each level, so a SIGTERM (or Ctrl-C) after the first leaves it, labelled partial, and no report.json.
TEST_F(InputSafety, InterruptedAdaptiveSolveKeepsItsCertifiedLevels) {
  const fs::path out = dir / "a";
  const fs::path levels = out / "adapt_levels.json";
  // A target far away (many levels); interrupted as soon as the first level is kept.
  const std::string cmd = "cd '" + dir.string() + "' && { " HEMICONTACT_CLI_PATH " solve " + FIG2 +
                          " --quiet --set mesh.n=16 --set adapt.target_error=0.0002 --set check.smallness=false --out " +
                          out.string() + " 2>err.txt & pid=$!; i=0; while [ ! -f '" + levels.string() +
                          "' ] && [ $i -lt 400 ]; do sleep 0.025; i=$((i+1)); done; kill -TERM $pid; wait $pid; "
                          "echo $? >code.txt; }";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  ASSERT_TRUE(fs::exists(levels)) << slurp(dir / "err.txt");
  EXPECT_FALSE(fs::exists(out / "report.json")) << "the run ended before the interrupt";
  EXPECT_EQ(std::stoi(slurp(dir / "code.txt")), 143) << slurp(dir / "err.txt");
  const json kept = json::parse(slurp(levels));
  EXPECT_TRUE(kept.at("partial").get<bool>());
  ASSERT_GE(kept.at("history").size(), 1u);
  for (const json& L : kept.at("history")) EXPECT_TRUE(L.at("ok").get<bool>());
  EXPECT_TRUE(has(slurp(dir / "err.txt"), "adapt_levels.json")) << "the interrupt message names what was kept";
}

// converge's options are bounded as the keys they stand for: --graded-power inf (or 50) failed
// later naming a degenerate cell; --reference adaptive:1e-9 was accepted below adapt.target_error's
// floor; a level above the 2^20 cap did not say what the cap is.
TEST_F(InputSafety, ConvergeOptionsHaveTheirKeysBounds) {
  const std::string study = "converge " + FIG2 + " --adaptive --quiet --out " + (dir / "s").string();
  auto r = cli(study + " --graded-power inf");
  EXPECT_EQ(r.code, hemicontact::EXIT_USAGE) << r.err;
  EXPECT_TRUE(has(r.err, "--graded-power: must be >= 1 and <= 10 (the range of scene key 'mesh.grading.power'), got inf"))
      << r.err;
  r = cli(study + " --graded-power 50");
  EXPECT_EQ(r.code, hemicontact::EXIT_USAGE) << r.err;
  r = cli(study + " --reference adaptive:1e-9 --levels 4 --graded-levels none");
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_TRUE(has(r.err, "--reference adaptive:T: must be > 1e-06 and < 1 (the range of scene key 'adapt.target_error')"))
      << r.err;
  r = cli("converge " + FIG2 + " --levels 4,2000000 --out " + (dir / "c").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_USAGE) << r.err;
  EXPECT_TRUE(has(r.err, "up to 1048576 (2^20 cells per side")) << r.err;
  r = cli("converge " + FIG2 + " --levels 4 --reference 4194304 --out " + (dir / "c").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_USAGE) << r.err;
  EXPECT_TRUE(has(r.err, "--reference: expected one positive integer up to 1048576")) << r.err;
}

// Gmsh merges <file>.opt after any file it opens, and an .opt file is a script: a m.msh.opt with
// SystemCall beside a valid m.msh ran the command and the solve still exited 0. End to end, through
// `hemicontact solve` on a Gmsh scene: the mesh is solved and nothing beside it runs.
TEST_F(InputSafety, AGmshMeshsCompanionOptFileIsNotRun) {
  if (!HEMICONTACT_HAS_GMSH) GTEST_SKIP() << "built without the Gmsh API (install libgmsh-dev)";
  fs::copy_file(HEMICONTACT_SOURCE_DIR "/tests/data/unit_square_3x3.msh", dir / "m.msh");
  const fs::path pwned = dir / "pwned";
  std::ofstream(dir / "m.msh.opt") << "SystemCall \"touch " << pwned.string() << "\";\n";
  const json scene = {{"mesh", {{"type", "gmsh"}, {"file", "m.msh"}}},
                      {"material", {{"E", 2000}, {"nu", 0.3}}},
                      {"boundary", {{"gamma1", {{{"physical", "clamped"}}}},
                                    {"gamma2", {{{"physical", "load"}, {"traction", {0, -50}}}}},
                                    {"gamma3", {{{"physical", "contact"}}}}}}};
  std::ofstream(dir / "scene.json") << scene.dump(2);
  const auto r = cli("solve " + (dir / "scene.json").string() + " --quiet --out " + (dir / "o").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_OK) << r.err;
  EXPECT_TRUE(fs::exists(dir / "o" / "report.json"));
  EXPECT_FALSE(fs::exists(pwned)) << "Gmsh ran the .opt file beside the mesh";
}
