// hemicontact — static frictional contact of an elastic body with a foundation covered by a soft
// layer, posed as a variational-hemivariational inequality (Sofonea, Han, Barboteu 2017).
//
// Sample runs:
//   hemicontact solve problems/sofonea2017-fig2.json --out out/fig2
//   hemicontact solve problems/sofonea2017-printed.json --set mesh.n=256 --out out/printed256
//   hemicontact solve problems/sofonea2017-fig2.json --backend ipopt --set solver.tol=1e-12
//   hemicontact solve problems/sofonea2017-fig2.json --out out/fig2 --plot     (+ out/fig2/fig2.png)
//   hemicontact converge problems/sofonea2017-fig2.json --levels 4,8,...,64 --reference 128 --plot
//   hemicontact minima problems/minima-softening.json --starts 16 --seed 3
//   hemicontact backends
//
// The problem (paper eqs. (1)-(6)): find u with σ = F(ε(u)), Div σ + f0 = 0 in Ω, u = 0 on Γ1,
// σν = f2 on Γ2, and on Γ3: u_ν ≤ g, σ_ν + ξ_ν ≤ 0, (u_ν − g)(σ_ν + ξ_ν) = 0, ξ_ν ∈ ∂j_ν(u_ν),
// |σ_τ| ≤ F_b(u_ν), −σ_τ = F_b(u_ν) u_τ/|u_τ| where u_τ ≠ 0. Discretized with P1 elements (22) and
// solved as min Π_λ(u) s.t. u_ν ≤ g with an outer fixed point on λ = F_b(u_ν) (docs/model.md §2).
#include "cli.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/process.hpp>
#include <hemicontact/output/output_dir.hpp>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>
#include <system_error>
#include <vector>

int main(int argc, char** argv) {
  using namespace hemicontact;
  // malloc thresholds and OpenMP's dynamic teams (src/core/process.cpp says why).
  configure_process_for_solves();
  const std::vector<std::string> args(argv + 1, argv + argc);
  // Ctrl-C or a kill while results are written: no half-written file under a final name, and a
  // word on what was kept (output/output_dir.hpp).
  install_interrupt_handlers();
  try {
    if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
      std::fputs(cli::usage().c_str(), args.empty() ? stderr : stdout);
      return args.empty() ? EXIT_USAGE : EXIT_OK;
    }
    const std::string cmd = args[0];
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    const bool known = cmd == "solve" || cmd == "backends" || cmd == "converge" || cmd == "minima" || cmd == "path";
    if (known && cli::wants_help(rest)) {
      std::fputs(cli::command_help(cmd).c_str(), stdout);
      return EXIT_OK;
    }
    if (cmd == "solve") return cli::cmd_solve(rest);
    if (cmd == "backends") return cli::cmd_backends(rest);
    if (cmd == "converge") return cli::cmd_converge(rest);
    if (cmd == "minima") return cli::cmd_minima(rest);
    if (cmd == "path") return cli::cmd_path(rest);
    if (cmd == "--version") {
      std::puts(cli::version().c_str());
      return EXIT_OK;
    }
    std::fprintf(stderr, "hemicontact: unknown command '%s' (see hemicontact --help)\n", cmd.c_str());
    return EXIT_USAGE;
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "hemicontact: %s (see hemicontact --help)\n", e.what());
    return EXIT_USAGE;
  } catch (const Error& e) {
    std::fprintf(stderr, "hemicontact: error: %s\n", e.what());
    return e.code();
  } catch (const std::bad_alloc&) {
    // Anywhere in a command (Eigen, std containers, Ipopt): a memory message and exit code 2, like
    // the memory estimate's refusal, never "internal error".
    const std::string what = "'hemicontact " + (args.empty() ? std::string() : args[0]) +
                             "' (an allocation failed: std::bad_alloc)";
    std::fprintf(stderr, "hemicontact: error: %s\n", out_of_memory_message(what).c_str());
    return EXIT_INPUT;
  } catch (const std::system_error& e) {
    // EAGAIN from creating a thread: under an address-space limit its stack did not fit.
    if (e.code() != std::errc::resource_unavailable_try_again) {
      std::fprintf(stderr, "hemicontact: internal error: %s\n", e.what());
      return EXIT_INTERNAL;
    }
    const std::string what = "'hemicontact " + (args.empty() ? std::string() : args[0]) +
                             "' (a thread could not be created: " + e.what() + ")";
    std::fprintf(stderr, "hemicontact: error: %s\n", out_of_memory_message(what).c_str());
    return EXIT_INPUT;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hemicontact: internal error: %s\n", e.what());
    return EXIT_INTERNAL;
  }
}
