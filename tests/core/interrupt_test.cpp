// The hooks for programs that embed the library (the Python module): the interrupt check the
// solve's loops poll (core/interrupt.hpp) and the log sink (core/log.hpp).
#include <hemicontact/config.hpp>
#include <hemicontact/core/interrupt.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

namespace hemicontact {
namespace {

const std::string INTERRUPT_FIG2 = HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json";

struct InterruptScene {
  nlohmann::json scene;
  Model model;
  SolveOptions opt;
};

InterruptScene interrupt_scene(const std::vector<std::string>& overrides) {
  InterruptScene s;
  s.scene = load_scene(INTERRUPT_FIG2, overrides);
  s.model = build_model(s.scene, scene_directory(INTERRUPT_FIG2));
  s.opt = solve_options_from_scene(s.scene);
  return s;
}

TEST(Interrupt, ACheckThatSaysStopEndsTheSolve) {
  const InterruptScene s = interrupt_scene({"mesh.n=8"});
  int polls = 0;
  {
    const ScopedInterruptCheck check([&] { return ++polls >= 2; });
    EXPECT_THROW(solve(s.model, s.opt), Interrupted);
  }
  EXPECT_EQ(polls, 2);  // sticky: not asked again once it said stop
  // Gone with its scope: the next solve runs to the end.
  const Solution sol = solve(s.model, s.opt);
  EXPECT_TRUE(sol.ok());
}

TEST(Interrupt, ACheckThatNeverStopsChangesNothing) {
  const InterruptScene s = interrupt_scene({"mesh.n=8"});
  const Solution plain = solve(s.model, s.opt);
  int polls = 0;
  const ScopedInterruptCheck check([&] {
    ++polls;
    return false;
  });
  const Solution checked = solve(s.model, s.opt);
  EXPECT_GT(polls, 0);
  EXPECT_EQ(plain.energy, checked.energy);
  EXPECT_EQ(plain.status_counts(), checked.status_counts());
}

TEST(Interrupt, IpoptStopsAtItsNextIteration) {
  if (!HEMICONTACT_HAS_IPOPT) GTEST_SKIP() << "built without Ipopt (coinor-libipopt-dev): nothing to interrupt";
  // The backend's stage only (exact.start = never): Ipopt's intermediate callback polls.
  const InterruptScene s = interrupt_scene({"mesh.n=8", "solver.backend=ipopt", "solver.exact.start=never"});
  int polls = 0;
  const ScopedInterruptCheck check([&] { return ++polls >= 3; });
  EXPECT_THROW(solve(s.model, s.opt), Interrupted);
}

TEST(Interrupt, TheCheckIsPerThread) {
  const ScopedInterruptCheck check([] { return true; });
  EXPECT_TRUE(interrupt_requested());
  bool other = true;
  std::thread t([&] { other = interrupt_requested(); });
  t.join();
  EXPECT_FALSE(other);
}

TEST(LogSink, TakesTheLinesInsteadOfStderr) {
  const InterruptScene s = interrupt_scene({"mesh.n=4"});
  std::vector<std::string> lines;
  const LogLevel before = log_level();
  set_log_level(LogLevel::INFO);
  set_log_sink([&](LogLevel level, const std::string& line) {
    if (level == LogLevel::INFO) lines.push_back(line);
  });
  solve(s.model, s.opt);
  set_log_sink(nullptr);
  set_log_level(before);
  bool formulation = false;
  for (const auto& l : lines) formulation = formulation || l.rfind("formulation", 0) == 0;
  EXPECT_TRUE(formulation) << lines.size() << " lines";
  const size_t n = lines.size();
  log_info() << "after the sink is gone";
  EXPECT_EQ(lines.size(), n);
}

}  // namespace
}  // namespace hemicontact
