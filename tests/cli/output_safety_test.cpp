// Issue 12, the output side, through the program: one run at a time per output folder (a lock),
// files written atomically with the report last, a failed write that says so with its own exit
// code (6) and leaves no report, an interrupt that removes the half-written file and names what
// was kept, and studies (minima) that keep each finished run as it ends.
#include <hemicontact/core/error.hpp>
#include <hemicontact/output/output_dir.hpp>

#include "support/cli_runner.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using hemicontact::test::lines_of;
using hemicontact::test::slurp;

class OutputSafety : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::temp_directory_path() /
          ("hemicontact_outsafe_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }

  static std::string scene(const std::string& name = "sofonea2017-fig2.json") {
    return std::string(HEMICONTACT_SOURCE_DIR "/problems/") + name;
  }

  /// Start `hemicontact ARGS` without waiting (stdout/stderr to files @p tag.out/.err in dir);
  /// @return its process id (the program itself: the shell execs it).
  pid_t start(const std::string& args, const std::string& tag) const {
    const std::string cmd = std::string("exec ") + HEMICONTACT_CLI_PATH + " " + args + " >" +
                            (dir / (tag + ".out")).string() + " 2>" + (dir / (tag + ".err")).string();
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    return pid;
  }

  /// Wait until @p p exists (a run reached a point), at most @p seconds. @return whether it did
  bool wait_for(const fs::path& p, double seconds = 60) const {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!fs::exists(p)) {
      if (std::chrono::steady_clock::now() > end) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
  }

  /// Files left under a temporary name (write_text_file's ".NAME.partial") in @p out.
  static std::vector<std::string> partials(const fs::path& out) {
    std::vector<std::string> r;
    for (const auto& e : fs::directory_iterator(out))
      if (e.path().filename().string().find(".partial") != std::string::npos) r.push_back(e.path().filename());
    return r;
  }

  fs::path dir;
};

// While one run holds the folder (here: this test process, through the same function the program
// uses), another is refused with exit 2 naming the holder; once it is released, the run goes ahead.
TEST_F(OutputSafety, ASecondRunIntoTheSameFolderIsRefused) {
  const fs::path out = dir / "res";
  {
    const hemicontact::OutputLock lock = hemicontact::prepare_output_dir(out.string(), false);
    ASSERT_TRUE(lock.held());
    const auto r = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=4 --out " + out.string());
    EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
    EXPECT_NE(r.err.find("--out '" + out.string() + "': another hemicontact run (pid " + std::to_string(::getpid()) +
                         ") is writing there"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(out / "report.json"));
  }
  const auto r = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=4 --out " + out.string());
  EXPECT_EQ(r.code, hemicontact::EXIT_OK) << r.err;
  EXPECT_TRUE(fs::exists(out / "report.json"));
}

// Two runs started together into one folder: exactly one writes its results and says so; the
// other exits 2 (it met the lock, or the finished set) and prints no "results in".
TEST_F(OutputSafety, TwoRunsStartedTogetherOneWinsAndTheOtherSaysWhy) {
  const fs::path out = dir / "res";
  const std::string args = "solve " + scene() + " --set mesh.n=16 --out " + out.string();
  const pid_t a = start(args, "a"), b = start(args, "b");
  int sa = 0, sb = 0;
  ASSERT_EQ(::waitpid(a, &sa, 0), a);
  ASSERT_EQ(::waitpid(b, &sb, 0), b);
  ASSERT_TRUE(WIFEXITED(sa) && WIFEXITED(sb));
  const int ca = WEXITSTATUS(sa), cb = WEXITSTATUS(sb);
  ASSERT_TRUE((ca == 0 && cb == 2) || (ca == 2 && cb == 0)) << "exit codes " << ca << " and " << cb;
  const std::string loser = ca == 2 ? "a" : "b", winner = ca == 2 ? "b" : "a";
  const std::string err = slurp(dir / (loser + ".err"));
  EXPECT_TRUE(err.find("another hemicontact run") != std::string::npos ||
              err.find("already holds results (report.json)") != std::string::npos)
      << err;
  EXPECT_EQ(slurp(dir / (loser + ".out")).find("results in"), std::string::npos);
  EXPECT_NE(slurp(dir / (winner + ".out")).find("results in"), std::string::npos);
  const json report = json::parse(slurp(out / "report.json"));
  EXPECT_TRUE(report.at("ok").get<bool>());
  EXPECT_TRUE(partials(out).empty());
}

// A write that fails (here a file-size limit, as a full disk would) exits 6 naming the file and
// the reason, leaves neither that file nor its temporary nor a report; the next run goes ahead
// without --force, since nothing was kept.
TEST_F(OutputSafety, AFailedWriteExitsSixAndLeavesNoReport) {
  const fs::path out = dir / "res";
  // The ASCII VTU at n = 64 is ~2.5 MB; the limit (ulimit -f, in blocks of 512 or 1024 bytes
  // depending on the shell) lets the small files through but not it.
  const std::string args =
      "solve " + scene() + " --set mesh.n=64 --set output.vtu_format='\"ascii\"' --out " + out.string();
  const auto r = hemicontact::test::run_cli(dir, args, "ulimit -f 400;");
  EXPECT_EQ(r.code, hemicontact::EXIT_OUTPUT) << r.err;
  EXPECT_NE(r.err.find("cannot write '" + (out / "solution.vtu").string() + "': File too large"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out / "report.json"));
  EXPECT_FALSE(fs::exists(out / "solution.vtu"));
  EXPECT_TRUE(partials(out).empty());
  EXPECT_EQ(r.out.find("results in"), std::string::npos);

  const auto again = hemicontact::test::run_cli(dir, args);
  EXPECT_EQ(again.code, hemicontact::EXIT_OK) << again.err;
  EXPECT_TRUE(json::parse(slurp(out / "report.json")).at("ok").get<bool>());
}

// SIGTERM during the run: the program ends by the signal (as the shell expects), says that the
// results are incomplete and what was kept, and leaves no report and no half-written file. A rerun
// into the folder needs --force only if something was kept, and then succeeds.
TEST_F(OutputSafety, AnInterruptedSolveLeavesNoReportAndSaysSo) {
  const fs::path out = dir / "res";
  const pid_t pid = start("solve " + scene() + " --set mesh.n=256 --out " + out.string(), "run");
  // The manifest appears when the folder is prepared: from then on the run is solving or writing.
  ASSERT_TRUE(wait_for(out / hemicontact::OUTPUT_MANIFEST));
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the n = 256 solve ended before the signal; exit " << WEXITSTATUS(status);
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  const std::string err = slurp(dir / "run.err");
  EXPECT_NE(err.find("hemicontact: interrupted: the results in '" + out.string() + "' are incomplete"),
            std::string::npos)
      << err;
  EXPECT_FALSE(fs::exists(out / "report.json"));
  EXPECT_TRUE(partials(out).empty());
  // Whatever is named as kept is complete (renamed into place only when fully written).
  if (fs::exists(out / "gamma3.csv")) {
    EXPECT_NE(slurp(out / "gamma3.csv").find('\n'), std::string::npos);
  }

  const auto again = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=8 --force --out " + out.string());
  EXPECT_EQ(again.code, hemicontact::EXIT_OK) << again.err;
  // The folder holds exactly the new set: what the report lists, nothing of the interrupted run.
  std::vector<std::string> listed = json::parse(slurp(out / "report.json")).at("files").get<std::vector<std::string>>();
  std::vector<std::string> present;
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().filename().string()[0] != '.') present.push_back(e.path().filename());
  std::sort(listed.begin(), listed.end());
  std::sort(present.begin(), present.end());
  EXPECT_EQ(present, listed);
}

// minima keeps each finished run as it ends (minima-runs.csv, rewritten atomically); an
// interrupt names it, and the runs it holds are whole rows; minima.json (the marker of a finished
// search) is not written.
TEST_F(OutputSafety, AnInterruptedMinimaSearchKeepsItsFinishedRuns) {
  const fs::path out = dir / "res";
  const pid_t pid =
      start("minima " + scene("minima-softening.json") + " --starts 10000 --load-path-steps 0 --out " + out.string(),
            "run");
  ASSERT_TRUE(wait_for(out / "minima-runs.csv"));
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGINT);
  const std::string err = slurp(dir / "run.err");
  EXPECT_NE(err.find("are incomplete (kept: minima-runs.csv"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out / "minima.json"));
  EXPECT_TRUE(partials(out).empty());
  const std::vector<std::string> rows = lines_of(slurp(out / "minima-runs.csv"));
  ASSERT_GE(rows.size(), 2u);
  EXPECT_EQ(rows[0], "run,start,backend,solved_by,converged,certified,energy,certificate,seconds,message");
  EXPECT_EQ(rows[1].rfind("0,zero,", 0), 0u) << rows[1];
  for (size_t i = 1; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].rfind(std::to_string(i - 1) + ",", 0), 0u) << rows[i];
    EXPECT_EQ(rows[i].back(), '"') << "a cut row: " << rows[i];
  }
  // A rerun without --force is refused: the kept runs are results.
  const auto again = hemicontact::test::run_cli(dir, "minima " + scene("minima-softening.json") + " --out " + out.string());
  EXPECT_EQ(again.code, hemicontact::EXIT_INPUT);
  EXPECT_NE(again.err.find("an incomplete set"), std::string::npos) << again.err;
}

}  // namespace
