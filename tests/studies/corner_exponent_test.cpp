// scripts/corner_exponent.py: the clamped-free corner exponent that docs/convergence.md uses to explain the
// observed convergence rate of the paper's scenes (≈ 0.72, not the O(h) of eq. (31)).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

namespace {

// Runs the script with @p args and returns the exponent it prints after "u ~ r^" (NaN if none).
double exponent(const std::string& args) {
  const std::string cmd = "/usr/bin/python3 " HEMICONTACT_SOURCE_DIR "/scripts/corner_exponent.py " + args + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
  std::string out;
  char buf[512];
  while (p && std::fgets(buf, sizeof buf, p.get())) out += buf;
  const auto at = out.find("u ~ r^");
  return at == std::string::npos ? std::nan("") : std::stod(out.substr(at + 6));
}

bool numpy_available() { return std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") == 0; }

}  // namespace

TEST(CornerExponent, MatchesWilliamsAndThePaperScene) {
  if (!numpy_available()) GTEST_SKIP() << "python3-numpy is not installed";
  // Williams (1952), clamped-free right angle, plane strain ν = 0.3: λ = 0.7112 (4 digits published).
  EXPECT_NEAR(exponent("--nu 0.3 --plane strain"), 0.7112, 5e-5);
  // The paper's material (plane stress, ν = 0.4): the rate fitted to the h = 1/1024 study is 0.72.
  EXPECT_NEAR(exponent("--nu 0.4 --plane stress"), 0.7205, 5e-5);
  // A 180° clamped-free transition has complex exponents only: the script must not invent a real one.
  EXPECT_TRUE(std::isnan(exponent("--nu 0.3 --plane strain --angle-deg 180")));
}
