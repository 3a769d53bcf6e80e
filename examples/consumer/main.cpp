// Solve a scene file with the installed library: what `hemicontact solve` does without the files.
// Usage: consumer SCENE.json [N]   (N: mesh.n). Prints the energy and the certificate; exits 0 when
// the answer is certified.
#include <hemicontact/output/report.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <cstdio>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: consumer SCENE.json [N]\n");
    return 1;
  }
  try {
    std::vector<std::string> overrides;
    if (argc > 2) overrides.push_back(std::string("mesh.n=") + argv[2]);
    const nlohmann::json scene = hemicontact::load_scene(argv[1], overrides);
    const hemicontact::Model model = hemicontact::build_model(scene, hemicontact::scene_directory(argv[1]));
    const hemicontact::Solution sol = hemicontact::solve(model, hemicontact::solve_options_from_scene(scene));
    std::printf("energy %.17g\ncertificate %s %.3g\nstatuses %s\n", sol.energy,
                sol.certificate.passed ? "passed" : "failed", sol.certificate.max_residual,
                hemicontact::status_runs(sol).c_str());
    return sol.ok() ? 0 : 4;
  } catch (const hemicontact::Error& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return e.code();
  }
}
