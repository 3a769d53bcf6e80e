// The output side, through the program: one run at a time per output folder (a lock),
// files written atomically with the report last, a failed write that says so with its own exit
// code (6) and leaves no report, an interrupt that removes the half-written file and names what
// was kept, and studies (minima) that keep each finished run as it ends.
#include <hemicontact/core/error.hpp>
#include <hemicontact/output/output_dir.hpp>

#include "support/cli_runner.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/stat.h>
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
  pid_t start(const std::string& args, const std::string& tag, const std::string& env = "") const {
    const std::string cmd = std::string("exec ") + (env.empty() ? "" : "env " + env + " ") + HEMICONTACT_CLI_PATH +
                            " " + args + " >" +
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
    // Under mpirun (its environment) the default engine is refused before the folder is touched,
    // saying what was meant: the petsc engine.
    const auto mpi = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=4 --out " + out.string(),
                                                "OMPI_COMM_WORLD_SIZE=2");
    EXPECT_NE(mpi.code, 0) << mpi.err;
    EXPECT_NE(mpi.err.find("solver.engine='\"petsc\"'"), std::string::npos) << mpi.err;
    EXPECT_EQ(mpi.err.find("is writing there"), std::string::npos) << mpi.err;
    EXPECT_EQ(r.err.find("mpirun"), std::string::npos) << r.err;
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
  // At once, with no pause: the interrupt message is rebuilt just after the file is renamed into
  // place, and a signal in between names the file from the message prepared before the rename.
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

// ---- a planted file in the output folder cannot redirect, hang or lose a run

/// The names of the entries of @p out that do not start with a dot.
std::vector<std::string> visible_files(const fs::path& out) {
  std::vector<std::string> r;
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().filename().string()[0] != '.') r.push_back(e.path().filename());
  std::sort(r.begin(), r.end());
  return r;
}

// A link planted under the report's temporary name made the report land in its target
// (exit 0). Now the run is refused before it starts, naming the link; the target is untouched.
// A FIFO under the manifest's name hung the run; now it is refused at once.
TEST_F(OutputSafety, ALinkOrFifoPlantedInTheFolderIsRefusedNamingIt) {
  const fs::path out = dir / "res";
  fs::create_directories(out);
  std::ofstream(dir / "victim") << "the user's\n";
  fs::create_symlink("../victim", out / ".report.json.partial");
  const auto r = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=8 --out " + out.string());
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_NE(r.err.find("'.report.json.partial' is a symbolic link, not a file hemicontact wrote"), std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(dir / "victim"), "the user's\n");
  EXPECT_FALSE(fs::exists(out / "report.json"));
  const auto forced = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=8 --force --out " + out.string());
  EXPECT_EQ(forced.code, hemicontact::EXIT_INPUT) << forced.err;
  EXPECT_EQ(slurp(dir / "victim"), "the user's\n");
  fs::remove(out / ".report.json.partial");

  ASSERT_EQ(::mkfifo((out / hemicontact::OUTPUT_MANIFEST).c_str(), 0600), 0);
  // `timeout`: a hang fails the test instead of blocking the suite.
  const auto fifo =
      hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=8 --out " + out.string(), "timeout 60");
  EXPECT_EQ(fifo.code, hemicontact::EXIT_INPUT) << fifo.err;
  EXPECT_NE(fifo.err.find(std::string(hemicontact::OUTPUT_MANIFEST) + " is not a file list written by hemicontact (it is a FIFO)"),
            std::string::npos)
      << fifo.err;
  fs::remove(out / hemicontact::OUTPUT_MANIFEST);
  const auto ok = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=8 --out " + out.string());
  EXPECT_EQ(ok.code, hemicontact::EXIT_OK) << ok.err;
  EXPECT_EQ(slurp(dir / "victim"), "the user's\n");
}

// A report.json of the user's made --force delete every file the run would write and the
// tool's picture names (fig2.png). A report.json proves nothing now: the run is refused naming it,
// --force or not, and every file stays.
TEST_F(OutputSafety, AForeignReportJsonDoesNotLetForceDeleteFiles) {
  const fs::path out = dir / "res";
  fs::create_directories(out);
  std::ofstream(out / "report.json") << "{\"mine\":1}\n";
  std::ofstream(out / "fig2.png") << "mine\n";
  std::ofstream(out / "notes.txt") << "mine\n";
  const auto r = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=8 --out " + out.string() + " --force");
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_NE(r.err.find("'report.json' exists and was not written by hemicontact"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(out / "report.json"), "{\"mine\":1}\n");
  EXPECT_EQ(slurp(out / "fig2.png"), "mine\n");
  EXPECT_EQ(slurp(out / "notes.txt"), "mine\n");
  // Without the report, fig2.png (a name solve may write) is refused the same way.
  fs::rename(out / "report.json", dir / "report.json");
  const auto again = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=8 --out " + out.string() + " --force");
  EXPECT_EQ(again.code, hemicontact::EXIT_INPUT) << again.err;
  EXPECT_NE(again.err.find("'fig2.png' exists and was not written by hemicontact"), std::string::npos) << again.err;
  EXPECT_EQ(slurp(out / "fig2.png"), "mine\n");
}

// converge overwrote a user's level_4.vtu and minima a user's solution_1.vtu, without
// --force. Both are refused before any solve, naming the file, which stays.
TEST_F(OutputSafety, ConvergeAndMinimaRefuseAUsersNumberedFileBeforeSolving) {
  const fs::path x = dir / "conv", y = dir / "min";
  fs::create_directories(x);
  fs::create_directories(y);
  std::ofstream(x / "level_4.vtu") << "mine\n";
  std::ofstream(y / "solution_1.vtu") << "mine\n";
  const auto c = hemicontact::test::run_cli(
      dir, "converge " + scene() + " --quiet --levels 4,8 --reference 16 --out " + x.string());
  EXPECT_EQ(c.code, hemicontact::EXIT_INPUT) << c.err;
  EXPECT_NE(c.err.find("'level_4.vtu' exists and was not written by hemicontact"), std::string::npos) << c.err;
  EXPECT_EQ(slurp(x / "level_4.vtu"), "mine\n");
  EXPECT_EQ(visible_files(x), std::vector<std::string>{"level_4.vtu"});
  const auto m = hemicontact::test::run_cli(
      dir, "minima " + scene("minima-softening.json") + " --quiet --starts 8 --out " + y.string() + " --force");
  EXPECT_EQ(m.code, hemicontact::EXIT_INPUT) << m.err;
  EXPECT_NE(m.err.find("'solution_1.vtu' exists and was not written by hemicontact"), std::string::npos) << m.err;
  EXPECT_EQ(slurp(y / "solution_1.vtu"), "mine\n");
  EXPECT_EQ(visible_files(y), std::vector<std::string>{"solution_1.vtu"});
}

// WEAK "Messages": a dangling --out link said "File exists"; a lock file that cannot be used was
// "directory is not writable" without its name. Both now name the file and the remedy.
TEST_F(OutputSafety, ADanglingOutLinkAndABadLockFileAreNamed) {
  fs::create_symlink(dir / "missing", dir / "res");
  const auto r = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=4 --out " + (dir / "res").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_INPUT) << r.err;
  EXPECT_NE(r.err.find("--out '" + (dir / "res").string() + "' is a symbolic link to '" + (dir / "missing").string() +
                       "', which does not exist"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "missing"));

  const fs::path out = dir / "locked";
  fs::create_directories(out / hemicontact::OUTPUT_LOCK);  // what no run can open for its lock
  const auto l = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=4 --out " + out.string());
  EXPECT_EQ(l.code, hemicontact::EXIT_INPUT) << l.err;
  EXPECT_NE(l.err.find("the lock file '" + (out / hemicontact::OUTPUT_LOCK).string() +
                       "' is a directory, not a regular file"),
            std::string::npos)
      << l.err;
  if (::geteuid() != 0) {  // root opens any file: a stale lock of another user needs a user
    fs::remove(out / hemicontact::OUTPUT_LOCK);
    std::ofstream(out / hemicontact::OUTPUT_LOCK) << "12345\n";
    fs::permissions(out / hemicontact::OUTPUT_LOCK, fs::perms::owner_read);
    const auto s = hemicontact::test::run_cli(dir, "solve " + scene() + " --set mesh.n=4 --out " + out.string());
    EXPECT_EQ(s.code, hemicontact::EXIT_OUTPUT) << s.err;
    EXPECT_NE(s.err.find("the lock file '" + (out / hemicontact::OUTPUT_LOCK).string() + "' cannot be opened"),
              std::string::npos)
        << s.err;
  }
}

// WEAK "Messages": SIGTERM while the picture is drawn left the plotting process running. The
// "python" here is a stand-in that records its process id and sleeps; it must end with the run.
TEST_F(OutputSafety, AnInterruptDuringThePlotEndsThePlottingProcess) {
  const fs::path python = dir / "slow-python", pidfile = dir / "plot.pid";
  std::ofstream(python) << "#!/bin/sh\necho $$ > " << pidfile.string() << ".tmp\nmv " << pidfile.string()
                        << ".tmp " << pidfile.string() << "\nexec sleep 120\n";
  fs::permissions(python, fs::perms::owner_all);
  const pid_t pid = start("solve " + scene() + " --quiet --set mesh.n=4 --plot --out " + (dir / "res").string(), "run",
                          "HEMICONTACT_PYTHON=" + python.string());
  ASSERT_TRUE(wait_for(pidfile));
  const pid_t child = static_cast<pid_t>(std::stol(slurp(pidfile)));
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  // Gone, or a zombie waiting for whoever adopted it: not running either way.
  const auto running = [&] {
    const std::string stat = slurp("/proc/" + std::to_string(child) + "/stat");
    const size_t paren = stat.rfind(')');
    return !stat.empty() && paren != std::string::npos && stat.size() > paren + 2 && stat[paren + 2] != 'Z';
  };
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (running() && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_FALSE(running()) << "the plotting process " << child << " outlived the run";
  if (running()) ::kill(child, SIGKILL);
}

// SIGTERM while the picture is drawn left .fig2.png.partial (the script's temporary), which the
// advised --force rerun then refused as a file not written by hemicontact. The stand-in
// "python" writes the temporary, then sleeps; the rerun's stand-in draws nothing.
TEST_F(OutputSafety, APictureInterruptedWhileDrawnDoesNotBlockForce) {
  const fs::path python = dir / "slow-python", ready = dir / "drawing", out = dir / "res";
  const fs::path partial = out / ".fig2.png.partial";
  std::ofstream(python) << "#!/bin/sh\necho half > " << partial.string() << "\ntouch " << ready.string()
                        << "\nexec sleep 120\n";
  fs::permissions(python, fs::perms::owner_all);
  const std::string args = "solve " + scene() + " --quiet --set mesh.n=4 --plot --out " + out.string();
  const pid_t pid = start(args, "run", "HEMICONTACT_PYTHON=" + python.string());
  ASSERT_TRUE(wait_for(ready));
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(fs::exists(partial)) << "the interrupted picture left no temporary: the case is not reproduced";
  const auto again = hemicontact::test::run_cli(dir, args + " --force", "HEMICONTACT_PYTHON=/bin/true");
  EXPECT_EQ(again.code, hemicontact::EXIT_OK) << again.err;
  EXPECT_FALSE(fs::exists(partial));
  // The picture the stand-in did not draw is not listed among the results.
  const json files = json::parse(slurp(out / "report.json")).at("files");
  EXPECT_EQ(std::find(files.begin(), files.end(), "fig2.png"), files.end()) << files;
}

}  // namespace
