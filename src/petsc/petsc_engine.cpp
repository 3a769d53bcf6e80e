#include "petsc_engine.hpp"

#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/contact/mollified_law.hpp>
#include <hemicontact/contact/smooth_norm.hpp>
#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/problem/node_rules.hpp>

#include <petscksp.h>
#include <petscmat.h>
#if HEMICONTACT_HAS_PTSCOTCH
#include <scotch/ptscotch.h>
#endif
#include <petsctao.h>
#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <initializer_list>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

// PETSc's Vec and Mat are global typedefs; inside namespace hemicontact the names are Eigen's, so
// PETSc objects are written ::Vec and ::Mat throughout.

namespace hemicontact::petsc_engine {
namespace {

// PETSc's first error message of the current failure (error_handler), and the user's options.
std::string g_petsc_message;
std::string g_user_options;

// A PETSc call that fails is a bug or a resource problem (EXIT_INTERNAL), or, with options of the
// user's set (solver.petsc.options), most likely one of them: EXIT_INPUT naming them.
[[noreturn]] void petsc_failure(PetscErrorCode ierr, const char* call) {
  std::string m = "PETSc error " + std::to_string(ierr) + " in " + call;
  if (!g_petsc_message.empty()) m += ": " + g_petsc_message;
  g_petsc_message.clear();
  if (ierr == PETSC_ERR_MEM) memory_error(m);
  if (g_user_options.empty()) throw Error(m, EXIT_INTERNAL);
  throw Error(m + " (solver.petsc.options = '" + g_user_options + "' is set: check its options)", EXIT_INPUT);
}
#define HC_PETSC(call)                                         \
  do {                                                         \
    const PetscErrorCode hc_ierr_ = (call);                    \
    if (hc_ierr_) petsc_failure(hc_ierr_, #call);              \
  } while (0)

// Owners of PETSc objects: destroyed on every rank in the same order (collective).
struct PVec {
  ::Vec v = nullptr;
  PVec() = default;
  PVec(const PVec&) = delete;
  PVec& operator=(const PVec&) = delete;
  ~PVec() {
    if (v) VecDestroy(&v);
  }
};
struct PMat {
  ::Mat m = nullptr;
  PMat() = default;
  PMat(const PMat&) = delete;
  PMat& operator=(const PMat&) = delete;
  ~PMat() {
    if (m) MatDestroy(&m);
  }
};
struct PKsp {
  KSP k = nullptr;
  PKsp() = default;
  PKsp(const PKsp&) = delete;
  PKsp& operator=(const PKsp&) = delete;
  ~PKsp() {
    if (k) KSPDestroy(&k);
  }
};
struct PTao {
  Tao t = nullptr;
  PTao() = default;
  PTao(const PTao&) = delete;
  PTao& operator=(const PTao&) = delete;
  ~PTao() {
    if (t) TaoDestroy(&t);
  }
};

std::string short_number(double x) {
  std::ostringstream os;
  os << std::setprecision(3) << x;
  return os.str();
}

double allreduce_max(double x, MPI_Comm comm) {
  double y = x;
  MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_MAX, comm);
  return y;
}
double allreduce_sum(double x, MPI_Comm comm) {
  double y = x;
  MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_SUM, comm);
  return y;
}

// A PETSc option's default: set only where the user set nothing (solver.petsc.options,
// PETSC_OPTIONS), so that theirs still wins.
void option_default(const std::string& name, const char* value) {
  PetscBool set = PETSC_FALSE;
  HC_PETSC(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set));
  if (!set) HC_PETSC(PetscOptionsSetValue(nullptr, name.c_str(), value));
}

// Option defaults for a KSP's preconditioner of type @p type, set under the PC's final prefix
// (after the KSP read its options) and read again, only where the user set nothing: the user's
// own options (solver.petsc.options, PETSC_OPTIONS) still win.
void pc_defaults(KSP ksp, PCType type, const std::string& stem,
                 std::initializer_list<std::pair<const char*, const char*>> values) {
  PC pc;
  HC_PETSC(KSPGetPC(ksp, &pc));
  PetscBool same = PETSC_FALSE;
  HC_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), type, &same));
  if (!same) return;
  const char* prefix = nullptr;
  HC_PETSC(PCGetOptionsPrefix(pc, &prefix));
  const std::string pre = std::string("-") + (prefix ? prefix : "") + stem;
  for (const auto& [name, value] : values) option_default(pre + name, value);
  HC_PETSC(PCSetFromOptions(pc));
}

// BoomerAMG for elasticity in 3D: HMIS coarsening, ext+i interpolation truncated to 4 entries, one
// level of aggressive coarsening and strong threshold 0.5 (hypre's recommendation for 3D; the
// defaults, tuned for 2D scalar problems, gave a grid complexity ~2 and 5x the time of a TAO solve
// here).
void hypre_defaults(KSP ksp) {
  pc_defaults(ksp, PCHYPRE, "pc_hypre_boomeramg_",
              {{"coarsen_type", "HMIS"}, {"interp_type", "ext+i"}, {"P_max", "4"}, {"agg_nl", "1"},
               {"strong_threshold", "0.5"}});
}

// GAMG with its own eigenvalue estimate for the Chebyshev smoothers on every set-up: PETSc 3.18
// passes the estimate of the prolongator smoothing to them by default (pc_gamg_use_sa_esteig),
// and on a hierarchy rebuilt for a matrix with Γ3 rows fixed (contact, stick) that made the
// preconditioner indefinite (CG: DIVERGED_INDEFINITE_PC at the first rebuild; measured on the 3D
// scene at n = 32, 48, 70). Set on every KSP that may run GAMG: ssn's steps, the elastic solve and
// the polish (create_cg), and TAO's Newton steps (newton_pc = gamg).
void gamg_defaults(KSP ksp) { pc_defaults(ksp, PCGAMG, "pc_gamg_", {{"use_sa_esteig", "false"}}); }

// GAMG for TAO's Newton steps (newton_pc = gamg), whose matrix is the Hessian on the inactive set:
// its size changes from step to step, and PETSc 3.18's GAMG keeps its levels' operators through a
// reset and then refuses the new size ("Cannot change local size of Amat after use", exit 3 of
// every tao:* run with gamg before). A shell preconditioner therefore makes a fresh GAMG at every
// set-up (TAO's matrix is new at every step, so BoomerAMG's hierarchy is rebuilt just as often).
struct FreshGamg {
  PC inner = nullptr;
  std::string prefix;  // TAO's KSP's, so -tao_pc_gamg_... options reach the inner GAMG
};

PetscErrorCode fresh_gamg_setup(PC pc) {
  FreshGamg* s = nullptr;
  PetscCall(PCShellGetContext(pc, &s));
  ::Mat A, P;
  PetscCall(PCGetOperators(pc, &A, &P));
  PetscCall(PCDestroy(&s->inner));
  PetscCall(PCCreate(PetscObjectComm(reinterpret_cast<PetscObject>(pc)), &s->inner));
  PetscCall(PCSetOptionsPrefix(s->inner, s->prefix.c_str()));
  PetscCall(PCSetType(s->inner, PCGAMG));
  PetscCall(PCSetOperators(s->inner, A, P));
  PetscBool set = PETSC_FALSE;
  const std::string esteig = "-" + s->prefix + "pc_gamg_use_sa_esteig";
  PetscCall(PetscOptionsHasName(nullptr, nullptr, esteig.c_str(), &set));
  if (!set) PetscCall(PetscOptionsSetValue(nullptr, esteig.c_str(), "false"));
  PetscCall(PCSetFromOptions(s->inner));
  PetscCall(PCSetUp(s->inner));
  return 0;
}

PetscErrorCode fresh_gamg_apply(PC pc, ::Vec x, ::Vec y) {
  FreshGamg* s = nullptr;
  PetscCall(PCShellGetContext(pc, &s));
  PetscCall(PCApply(s->inner, x, y));
  return 0;
}

PetscErrorCode fresh_gamg_destroy(PC pc) {
  FreshGamg* s = nullptr;
  PetscCall(PCShellGetContext(pc, &s));
  PetscCall(PCDestroy(&s->inner));
  delete s;
  return 0;
}

void fresh_gamg(KSP ksp) {
  PC pc;
  HC_PETSC(KSPGetPC(ksp, &pc));
  PetscBool gamg = PETSC_FALSE;
  HC_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCGAMG, &gamg));
  if (!gamg) return;  // the user's -tao_pc_type won
  const char* prefix = nullptr;
  HC_PETSC(KSPGetOptionsPrefix(ksp, &prefix));
  HC_PETSC(PCSetType(pc, PCSHELL));
  auto* s = new FreshGamg;
  s->prefix = prefix ? prefix : "";
  HC_PETSC(PCShellSetContext(pc, s));
  HC_PETSC(PCShellSetSetUp(pc, fresh_gamg_setup));
  HC_PETSC(PCShellSetApply(pc, fresh_gamg_apply));
  HC_PETSC(PCShellSetDestroy(pc, fresh_gamg_destroy));
  HC_PETSC(PCShellSetName(pc, "GAMG, made anew for each Newton step"));
}

}  // namespace

namespace {
// PETSc's default handler prints a traceback on every rank and, with some options, aborts the
// job; this one keeps the first message of a failure for petsc_failure's Error and returns the
// code, so the error ends as every other: one message, one exit code.
PetscErrorCode error_handler(MPI_Comm, int, const char* fun, const char*, PetscErrorCode n, PetscErrorType p,
                             const char* mess, void*) {
  if (p == PETSC_ERROR_INITIAL || g_petsc_message.empty())
    g_petsc_message = std::string(mess ? mess : "") + (fun ? std::string(" (in ") + fun + ")" : std::string());
  return n;
}
}  // namespace

void install_error_handler(const std::string& user_options) {
  g_user_options = user_options;
  PetscPushErrorHandler(error_handler, nullptr);
}

long current_rss_kb() {
  long pages = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

namespace {

long peak_rss_kb() {
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss;  // Linux: kilobytes
}

}  // namespace

std::string tao_type(const std::string& backend) {
  // solver.backend = auto: this engine's own, ssn, which reaches the cholmod engine's answers ~10x
  // faster than tao:bnls (docs/petsc-engine.md). A backend of the cholmod engine that is named
  // is refused below: a named backend runs, or the run stops saying why.
  if (backend == AUTO_BACKEND) return "ssn";
  for (const char* t : {"bnls", "bntr", "bntl"})
    if (backend == std::string("tao:") + t) return t;
  if (backend == "ssn") return "ssn";  // not TAO: the engine's own semismooth Newton (run_ssn)
  input_error("solver.backend = '" + backend +
              "': the petsc engine runs ssn (semismooth Newton on the unsmoothed statuses) or TAO's "
              "bounded Newton methods tao:bnls, tao:bntr, tao:bntl (other backends: solver.engine = cholmod)");
}

namespace {
// The distributed problem: K, f and the bounds in PETSc, the Γ3 nodes this rank owns, the smoothing
// and frozen friction bounds, and the counters for the report.
class Engine {
 public:
  Engine(Model& md, const SolveOptions& opt, MPI_Comm comm, EngineReport& rep);
  ~Engine() {
    if (rigid) MatNullSpaceDestroy(&rigid);
    // K lives no longer than the engine: after the solve, nothing may apply it.
    if (owns_apply)
      md.Kx_apply = [](const Vec&) -> Vec {
        throw Error("K_x is not kept after the petsc engine's solve (its rows lived on the ranks)", EXIT_INTERNAL);
      };
  }
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;
  Solution run();

 private:
  Solution run_ssn(clk::time_point t0);
  // The rows of K that ssn's J changes (those with a column on a Γ3 unknown), saved so that K can
  // be changed in place and put back exactly.
  struct BandRows {
    std::vector<PetscInt> rows, start, cols;  // row r's entries: cols[start[r] .. start[r + 1])
    std::vector<PetscScalar> vals;
  };
  BandRows save_band() const;
  void restore_band(const BandRows& b) const;
  // ---- set-up
  void distribute();
  void assemble();
  void tao_vectors();  // the bounds and TAO's work vectors (not made for ssn)
  void near_null_space();
  void elastic_solve();
  // ---- the smoothed energy in scaled unknowns (callbacks of TAO)
  double energy(::Vec zs, ::Vec g);  // value, and the gradient into g (scaled)
  void hessian(::Vec zs, ::Mat H);   // K + nodal blocks, scaled; normal term clamped ≥ 0
  static PetscErrorCode tao_objgrad(Tao, ::Vec x, PetscReal* f, ::Vec g, void* ctx);
  static PetscErrorCode tao_hessian(Tao, ::Vec x, ::Mat H, ::Mat Hpre, void* ctx);
  // ---- the algorithm
  OuterIteration minimize(size_t stage);
  void relax_lambda(OuterIteration& rec, bool measure_contraction, double& prev_delta);
  bool run_stage(size_t stage);
  bool settled() const;
  PolishResult polish(Eigen::VectorXd& x, const SolveOptions& read_opt, const Solution& s0);
  PolishResult polish_with_readings(Eigen::VectorXd& x, size_t stage);
  void finish(Solution& sol, Eigen::VectorXd x, clk::time_point t0);
  // ---- helpers
  Eigen::VectorXd gather(::Vec v) const;  // the whole vector on every rank
  Eigen::VectorXd local_gamma3(::Vec zs) const;
  double first_order_residual(::Vec zs, ::Vec g, ::Vec lo_s, ::Vec up_s) const;
  void scaled_bound(::Vec b, ::Vec out) const;  // b / U_s, ±PETSC_INFINITY kept (no overflow)
  void ksp_check(KSP ksp, const std::string& what) const;
  void set_pc(KSP ksp, const std::string& type) const;
  void create_cg(PKsp& ksp, const char* prefix, KSPNormType norm = KSP_NORM_DEFAULT) const;
  Solution evaluate(const Eigen::VectorXd& x, const SolveOptions& o) const;

  Model& md;  // not changed
  SolveOptions opt;
  MPI_Comm comm;
  EngineReport& rep;
  int rank = 0, size = 1, d = 2, bs = 1;
  PetscInt n = 0, lo = 0, hi = 0;  // global size, owned rows [lo, hi) (PETSc's numbering)
  // PETSc's numbering of the unknowns is the model's x numbering (DofMap: interior node-major,
  // then Γ3) with the nodes regrouped by the graph partitioner's parts (solver.petsc.partition),
  // each node's d unknowns kept together. Both empty: the same numbering (one rank, "natural").
  std::vector<PetscInt> perm;  // x index → PETSc index
  std::vector<Index> mine;     // x index of owned row lo + l
  std::vector<char> own_nodes;  // per mesh node: its rows are this rank's (kept until assembled)
  PetscInt P(Index x) const { return perm.empty() ? static_cast<PetscInt>(x) : perm[static_cast<size_t>(x)]; }
  Index X(PetscInt l) const { return mine.empty() ? lo + l : mine[static_cast<size_t>(l)]; }
  // Γ3 node k's ν row in PETSc's numbering; its τ rows follow it.
  PetscInt cdof(Index k) const { return P(md.dofs.contact_dof(k, 0)); }
  void partition(const std::vector<Index>& block_node, const std::vector<PetscInt>& block_first,
                 const std::vector<int>& block_size);
  std::vector<Index> my_nodes;     // Γ3 nodes whose rows this rank owns
  PMat K;
  PVec f, lower, upper, zs, zfree, work, grad;
  MatNullSpace rigid = nullptr;
  double U_s = 1, F_s = 1;
  std::vector<std::pair<double, double>> schedule;
  double eps_tau = 0, eps_nu = 0;                // absolute widths of the current stage
  std::unique_ptr<MollifiedLaw> law;             // the mollified p_ν of the current stage
  std::vector<double> lambda;                    // frozen F_b per owned Γ3 node (my_nodes order)
  Eigen::VectorXd prev_c;                        // owned Γ3 unknowns after the previous minimization
  bool lagged = false;
  Solution sol;  // the answer being built (history, verdicts)
  int k_total = 0;
  long newton_total = 0, krylov_total = 0, polish_krylov = 0, polish_newton = 0;
  nlohmann::json stages = nlohmann::json::array();
  std::map<std::string, double> timings;
  bool owns_apply = false;  // md.Kx_apply set by assemble(), reading K and work
};

Engine::Engine(Model& m, const SolveOptions& o, MPI_Comm c, EngineReport& r) : md(m), opt(o), comm(c), rep(r) {
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  d = md.dim();
  if (!md.material->is_linear())
    input_error("solver.engine = petsc: linear materials only (" + md.material->describe() +
                "); a nonlinear material needs solver.engine = cholmod");
  (void)tao_type(opt.backend);  // refuse a non-TAO backend before any work
  // A rank without a cell of its own has no rows to assemble: refused, naming both counts.
  if (size > md.mesh.num_cells())
    input_error("solver.engine = petsc: " + std::to_string(size) + " MPI ranks for a mesh of " +
                std::to_string(md.mesh.num_cells()) + " cells; use at most as many ranks as cells (mpirun -np)");
  lagged = md.friction && md.friction->depends_on_u_nu();
}

// Row blocks: one node's d unknowns per block when every free node has all d components (no roller),
// so that GAMG aggregates nodes and a Γ3 node's (ν, τ) rows never straddle two ranks; otherwise
// blocks of 1 with the split still at node boundaries. The nodes go to the ranks as the graph
// partitioner says (solver.petsc.partition), or in contiguous runs of x ("natural").
void Engine::distribute() {
  const auto t0 = clk::now();
  n = static_cast<PetscInt>(md.dofs.n_free());
  bool rollers = false;
  for (Index v = 0; v < md.mesh.num_nodes(); ++v) rollers = rollers || md.mesh.held(v) != 0;
  bs = (!rollers && md.dofs.n_interior() % d == 0) ? d : 1;
  // The free nodes in x order, each with its first x index and its count of free components
  // (consecutive in x: interior nodes node-major, a Γ3 node's d local slots together).
  std::vector<Index> block_node;
  std::vector<PetscInt> block_first;
  std::vector<int> block_size;
  {
    const std::vector<Index> sel = md.dofs.cartesian_selection();
    std::vector<PetscInt> first_of(static_cast<size_t>(md.mesh.num_nodes()), -1);
    std::vector<int> count_of(static_cast<size_t>(md.mesh.num_nodes()), 0);
    for (size_t j = 0; j < sel.size(); ++j) {
      if (sel[j] < 0) continue;
      const size_t a = j / static_cast<size_t>(d);
      const auto xj = static_cast<PetscInt>(sel[j]);
      first_of[a] = first_of[a] < 0 ? xj : std::min(first_of[a], xj);
      ++count_of[a];
    }
    std::vector<Index> node_at(static_cast<size_t>(n), -1);  // node of each block's first x index
    for (size_t a = 0; a < first_of.size(); ++a)
      if (first_of[a] >= 0) node_at[static_cast<size_t>(first_of[a])] = static_cast<Index>(a);
    for (PetscInt i = 0; i < n; ++i)
      if (node_at[static_cast<size_t>(i)] >= 0) {
        const Index a = node_at[static_cast<size_t>(i)];
        block_node.push_back(a);
        block_first.push_back(i);
        block_size.push_back(count_of[static_cast<size_t>(a)]);
      }
  }
  const auto blocks = static_cast<PetscInt>(block_node.size());
  if (size > blocks)
    input_error("solver.engine = petsc: " + std::to_string(size) + " MPI ranks for " + std::to_string(blocks) +
                " free nodes; use at most as many ranks as free nodes (mpirun -np)");
  const auto at = [&](PetscInt b) { return b >= blocks ? n : block_first[static_cast<size_t>(b)]; };
  lo = at(blocks * rank / size);
  hi = at(blocks * (rank + 1) / size);
  rep.json["partition"] = {{"type", size > 1 ? opt.petsc.partition : "natural"}};
  if (size > 1 && opt.petsc.partition != "natural") partition(block_node, block_first, block_size);
  for (Index k = 0; k < md.contact.size(); ++k)
    if (cdof(k) >= lo && cdof(k) < hi) my_nodes.push_back(k);
  lambda.assign(my_nodes.size(), 0.0);
  own_nodes.assign(static_cast<size_t>(md.mesh.num_nodes()), 0);
  for (size_t b = 0; b < block_node.size(); ++b)
    if (P(block_first[b]) >= lo && P(block_first[b]) < hi) own_nodes[static_cast<size_t>(block_node[b])] = 1;
  timings["petsc_partition"] = since(t0);
}

// The graph partitioner (PT-Scotch, through MatPartitioning; -mat_partitioning_type picks another
// one PETSc has) on the free nodes' graph, each node weighted by its unknowns: the parts become
// the ranks' rows, numbered part by part in x order within each. Each rank gives the graph of the
// nodes of its natural run (lo, hi from distribute()); every rank then knows every node's part.
void Engine::partition(const std::vector<Index>& block_node, const std::vector<PetscInt>& block_first,
                       const std::vector<int>& block_size) {
  const auto blocks = static_cast<PetscInt>(block_node.size());
  const PetscInt b0 = blocks * rank / size, b1 = blocks * (rank + 1) / size, nb = b1 - b0;
  std::vector<PetscInt> block_of(static_cast<size_t>(md.mesh.num_nodes()), -1);
  for (PetscInt b = 0; b < blocks; ++b) block_of[static_cast<size_t>(block_node[static_cast<size_t>(b)])] = b;
  std::vector<char> keep(static_cast<size_t>(md.mesh.num_nodes()), 0);
  for (PetscInt b = b0; b < b1; ++b) keep[static_cast<size_t>(block_node[static_cast<size_t>(b)])] = 1;
  const NodeGraph g = node_graph(md.mesh, &keep);
  keep = std::vector<char>();
  // MatMPIAdj takes ia, ja (and the weights) over: PetscMalloc'd, no diagonal, sorted rows.
  PetscInt *ia = nullptr, *ja = nullptr, *wt = nullptr;
  HC_PETSC(PetscMalloc1(nb + 1, &ia));
  ia[0] = 0;
  for (PetscInt b = b0; b < b1; ++b) {
    const Index a = block_node[static_cast<size_t>(b)];
    PetscInt c = 0;
    for (const int* q = g.begin(a); q != g.end(a); ++q) c += block_of[static_cast<size_t>(*q)] >= 0 && *q != a;
    ia[b - b0 + 1] = ia[b - b0] + c;
  }
  HC_PETSC(PetscMalloc1(ia[nb], &ja));
  for (PetscInt b = b0; b < b1; ++b) {
    const Index a = block_node[static_cast<size_t>(b)];
    PetscInt* dst = ja + ia[b - b0];
    for (const int* q = g.begin(a); q != g.end(a); ++q)
      if (block_of[static_cast<size_t>(*q)] >= 0 && *q != a) *dst++ = block_of[static_cast<size_t>(*q)];
    std::sort(ja + ia[b - b0], dst);
  }
  ::Mat adj;
  HC_PETSC(MatCreateMPIAdj(comm, nb, blocks, ia, ja, nullptr, &adj));
  MatPartitioning mp;
  HC_PETSC(MatPartitioningCreate(comm, &mp));
  HC_PETSC(MatPartitioningSetAdjacency(mp, adj));
  HC_PETSC(MatPartitioningSetType(mp, MATPARTITIONINGPTSCOTCH));
  HC_PETSC(MatPartitioningSetNParts(mp, size));
  if (bs == 1) {  // rollers: nodes with fewer than d unknowns weigh less
    HC_PETSC(PetscMalloc1(nb, &wt));
    for (PetscInt b = b0; b < b1; ++b) wt[b - b0] = block_size[static_cast<size_t>(b)];
    HC_PETSC(MatPartitioningSetVertexWeights(mp, wt));
  }
  HC_PETSC(MatPartitioningSetFromOptions(mp));
  // Reproducible parts: Debian's Scotch runs its algorithms on threads and seeds its generator from
  // the clock, so the same run got different parts (3D scene, 24³, 2 ranks: 22 500 / 22 344 /
  // 22 566 rows on rank 0 in three runs, and 112, 139, 137 CG iterations). One thread per rank
  // (SCOTCH_PTHREAD_NUMBER, unless the user set it; the ranks already take the cores) and a fixed
  // seed make the partition, and every count that follows from it, the same each time.
  setenv("SCOTCH_PTHREAD_NUMBER", "1", 0);
#if HEMICONTACT_HAS_PTSCOTCH
  SCOTCH_randomSeed(1);
  SCOTCH_randomReset();
#endif
  IS part, all;
  HC_PETSC(MatPartitioningApply(mp, &part));
  HC_PETSC(ISAllGather(part, &all));
  const PetscInt* owner;
  HC_PETSC(ISGetIndices(all, &owner));
  // Part by part, x order within each: a counting sort of the blocks by owner.
  std::vector<PetscInt> part_start(static_cast<size_t>(size) + 1, 0);
  for (PetscInt b = 0; b < blocks; ++b) {
    if (owner[b] < 0 || owner[b] >= size) throw Error("petsc: the partitioner returned a part out of range", EXIT_INTERNAL);
    part_start[static_cast<size_t>(owner[b]) + 1] += block_size[static_cast<size_t>(b)];
  }
  for (int r = 0; r < size; ++r) part_start[static_cast<size_t>(r) + 1] += part_start[static_cast<size_t>(r)];
  perm.assign(static_cast<size_t>(n), -1);
  std::vector<PetscInt> next(part_start.begin(), part_start.end() - 1);
  for (PetscInt b = 0; b < blocks; ++b) {
    PetscInt& at = next[static_cast<size_t>(owner[b])];
    for (int c = 0; c < block_size[static_cast<size_t>(b)]; ++c)
      perm[static_cast<size_t>(block_first[static_cast<size_t>(b)] + c)] = at++;
  }
  HC_PETSC(ISRestoreIndices(all, &owner));
  ISDestroy(&all);
  ISDestroy(&part);
  MatPartitioningDestroy(&mp);
  MatDestroy(&adj);
  lo = part_start[static_cast<size_t>(rank)];
  hi = part_start[static_cast<size_t>(rank) + 1];
  mine.assign(static_cast<size_t>(hi - lo), -1);
  for (PetscInt x = 0; x < n; ++x) {
    const PetscInt p = perm[static_cast<size_t>(x)];
    if (p >= lo && p < hi) mine[static_cast<size_t>(p - lo)] = x;
  }
}

// Each rank copies its rows of the reduced stiffness Kx (symmetric, so row i is column i of the
// column-major matrix) with exact preallocation, and its part of f and of the bounds.
void Engine::assemble() {
  const auto t0 = clk::now();
  // The model built by hemicontact-mpi keeps no K_x (build_model(..., stiffness = false)): this
  // rank assembles its own columns, i.e. rows, and frees them once PETSc holds them. A model that
  // does keep K_x (tests that build one) is read as it is.
  MovableSpMat own;
  if (md.Kx.size() == 0)
    own = assemble_reduced_stiffness(md.mesh, md.material->tangent(Vec::Zero(voigt_size(d))), md.dofs, own_nodes);
  own_nodes = std::vector<char>();
  const SpMat& Kx = md.Kx.size() == 0 ? static_cast<const SpMat&>(own) : static_cast<const SpMat&>(md.Kx);
  const PetscInt nloc = hi - lo;
  std::vector<PetscInt> dnz(static_cast<size_t>(nloc), 0), onz(static_cast<size_t>(nloc), 0);
  long off_rank = 0, entries = 0;
  for (PetscInt l = 0; l < nloc; ++l)
    for (SpMat::InnerIterator it(Kx, X(l)); it; ++it) {
      const PetscInt r = P(it.row());
      (r >= lo && r < hi ? dnz : onz)[static_cast<size_t>(l)]++;
    }
  for (PetscInt l = 0; l < nloc; ++l) off_rank += onz[static_cast<size_t>(l)], entries += dnz[static_cast<size_t>(l)] + onz[static_cast<size_t>(l)];
  // The partition's quality: the share of K's entries that couple two ranks (each is a value sent
  // in every product) and the most rows on one rank against the mean.
  const double off_all = allreduce_sum(double(off_rank), comm), entries_all = allreduce_sum(double(entries), comm);
  rep.json["partition"]["off_rank_entries"] = entries_all > 0 ? off_all / entries_all : 0.0;
  std::vector<long> rows(static_cast<size_t>(size));
  long my_rows = nloc;
  MPI_Allgather(&my_rows, 1, MPI_LONG, rows.data(), 1, MPI_LONG, comm);
  rep.json["partition"]["rows_per_rank"] = rows;
  rep.json["partition"]["imbalance"] = n > 0 ? double(*std::max_element(rows.begin(), rows.end())) * size / double(n) : 1.0;
  HC_PETSC(MatCreate(comm, &K.m));
  HC_PETSC(MatSetSizes(K.m, nloc, nloc, n, n));
  HC_PETSC(MatSetType(K.m, MATAIJ));
  HC_PETSC(MatSetBlockSize(K.m, bs));
  HC_PETSC(MatSeqAIJSetPreallocation(K.m, 0, dnz.data()));
  HC_PETSC(MatMPIAIJSetPreallocation(K.m, 0, dnz.data(), 0, onz.data()));
  std::vector<PetscInt> cols;
  std::vector<PetscScalar> vals;
  for (PetscInt l = 0; l < nloc; ++l) {
    cols.clear();
    vals.clear();
    for (SpMat::InnerIterator it(Kx, X(l)); it; ++it) {
      cols.push_back(P(it.row()));
      vals.push_back(it.value());
    }
    const PetscInt i = lo + l;
    HC_PETSC(MatSetValues(K.m, 1, &i, static_cast<PetscInt>(cols.size()), cols.data(), vals.data(), INSERT_VALUES));
  }
  HC_PETSC(MatAssemblyBegin(K.m, MAT_FINAL_ASSEMBLY));
  HC_PETSC(MatAssemblyEnd(K.m, MAT_FINAL_ASSEMBLY));
  HC_PETSC(MatSetOption(K.m, MAT_SYMMETRIC, PETSC_TRUE));
  own = MovableSpMat();
  // Without K_x in the model, the certificate's internal force and a(u, u) (evaluate_solution)
  // apply this rank's rows through PETSc: every rank evaluates the same candidates together.
  if (md.Kx.size() == 0) {
    md.Kx_apply = [this](const Vec& x) {
      PVec xv, y;
      HC_PETSC(MatCreateVecs(K.m, &xv.v, &y.v));
      PetscScalar* p;
      HC_PETSC(VecGetArray(xv.v, &p));
      for (PetscInt l = 0; l < hi - lo; ++l) p[l] = x[X(l)];
      HC_PETSC(VecRestoreArray(xv.v, &p));
      HC_PETSC(MatMult(K.m, xv.v, y.v));
      return gather(y.v);
    };
    owns_apply = true;
  }

  HC_PETSC(MatCreateVecs(K.m, &f.v, nullptr));
  PetscScalar* pf;
  HC_PETSC(VecGetArray(f.v, &pf));
  for (PetscInt l = 0; l < hi - lo; ++l) pf[l] = md.fx[X(l)];
  HC_PETSC(VecRestoreArray(f.v, &pf));
  // The bounds and the TAO path's work vectors: ssn reads g and the rollers from the model.
  if (tao_type(opt.backend) != "ssn") tao_vectors();
  timings["petsc_assembly"] = since(t0);
  malloc_trim(0);  // the rank's own K_x and node graph, freed above, back to the system
  log_info() << "petsc: " << size << " rank(s), rows " << lo << ".." << hi << " of " << n << " on rank 0, assembled in "
             << short_number(timings["petsc_assembly"]) << " s, memory " << short_number(double(current_rss_kb()) / 1024.0)
             << " MB (rank 0)";
}

void Engine::tao_vectors() {
  for (PVec* v : {&lower, &upper, &zs, &zfree, &work, &grad}) HC_PETSC(MatCreateVecs(K.m, &v->v, nullptr));
  PetscScalar *pl, *pu;
  HC_PETSC(VecGetArray(lower.v, &pl));
  HC_PETSC(VecGetArray(upper.v, &pu));
  for (PetscInt i = lo; i < hi; ++i) {
    pl[i - lo] = PETSC_NINFINITY;
    pu[i - lo] = PETSC_INFINITY;
  }
  for (Index k : my_nodes) {
    const Index i = cdof(k) - lo;
    if (std::isfinite(md.contact.g[k])) pu[i] = md.contact.g[k];
    // A roller on a Γ3 node: 0 ≤ x_τ ≤ 0 keeps d unknowns per node (driver/solve.cpp does the same).
    for (int c = 1; c < d; ++c)
      if (roller_fixed(md, k, c)) pl[i + c] = pu[i + c] = 0;
  }
  HC_PETSC(VecRestoreArray(lower.v, &pl));
  HC_PETSC(VecRestoreArray(upper.v, &pu));
}

// The rigid-body modes of the body (2D: 2 translations, 1 rotation; 3D: 3 + 3) in the reduced
// unknowns, x = Tᵀ r (DofMap: Γ3 nodes in their local frames), orthonormalized: GAMG's near-null
// space (solver.petsc.near_null_space: the translations only, or all of them).
void Engine::near_null_space() {
  const Index N = md.mesh.num_nodes();
  const int nm = opt.petsc.near_null_space == "rigid" ? (d == 2 ? 3 : 6) : d;
  std::vector<::Vec> modes(static_cast<size_t>(nm), nullptr);
  for (int m = 0; m < nm; ++m) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(N * d);
    for (Index v = 0; v < N; ++v) {
      const auto x = md.mesh.points.row(v);
      if (m < d) {
        r[d * v + m] = 1;
      } else if (d == 2) {
        r[2 * v] = -x[1], r[2 * v + 1] = x[0];
      } else {  // rotation about axis a: e_a × x
        const int a = m - 3, b = (a + 1) % 3, c = (a + 2) % 3;
        r[3 * v + b] = -x[c], r[3 * v + c] = x[b];
      }
    }
    const Eigen::VectorXd rx = md.dofs.to_reduced(r);
    HC_PETSC(MatCreateVecs(K.m, &modes[static_cast<size_t>(m)], nullptr));
    PetscScalar* p;
    HC_PETSC(VecGetArray(modes[static_cast<size_t>(m)], &p));
    for (PetscInt l = 0; l < hi - lo; ++l) p[l] = rx[X(l)];
    HC_PETSC(VecRestoreArray(modes[static_cast<size_t>(m)], &p));
  }
  // Modified Gram-Schmidt (MatNullSpaceCreate wants orthonormal vectors).
  for (int m = 0; m < nm; ++m) {
    for (int q = 0; q < m; ++q) {
      PetscScalar dot;
      HC_PETSC(VecDot(modes[static_cast<size_t>(m)], modes[static_cast<size_t>(q)], &dot));
      HC_PETSC(VecAXPY(modes[static_cast<size_t>(m)], -dot, modes[static_cast<size_t>(q)]));
    }
    PetscReal nrm;
    HC_PETSC(VecNormalize(modes[static_cast<size_t>(m)], &nrm));
  }
  HC_PETSC(MatNullSpaceCreate(comm, PETSC_FALSE, nm, modes.data(), &rigid));
  HC_PETSC(MatSetNearNullSpace(K.m, rigid));
  for (auto& v : modes) VecDestroy(&v);
}

void Engine::set_pc(KSP ksp, const std::string& type) const {
  PC pc;
  HC_PETSC(KSPGetPC(ksp, &pc));
  if (type == "hypre") {
    HC_PETSC(PCSetType(pc, PCHYPRE));
    HC_PETSC(PCHYPRESetType(pc, "boomeramg"));
  } else {
    HC_PETSC(PCSetType(pc, PCGAMG));
  }
}

// CG with the full-size preconditioner (solver.petsc.pc) at ksp_rtol, under the options prefix
// @p prefix: the elastic solve, the polish and ssn's steps. The user's PETSc options, read last,
// win over these settings.
void Engine::create_cg(PKsp& ksp, const char* prefix, KSPNormType norm) const {
  HC_PETSC(KSPCreate(comm, &ksp.k));
  HC_PETSC(KSPSetType(ksp.k, KSPCG));
  HC_PETSC(KSPSetOptionsPrefix(ksp.k, prefix));
  if (norm != KSP_NORM_DEFAULT) HC_PETSC(KSPSetNormType(ksp.k, norm));
  set_pc(ksp.k, opt.petsc.pc);
  HC_PETSC(KSPSetTolerances(ksp.k, opt.petsc.ksp_rtol, PETSC_DEFAULT, PETSC_DEFAULT, opt.petsc.ksp_max_it));
  HC_PETSC(KSPSetFromOptions(ksp.k));
  hypre_defaults(ksp.k);
  gamg_defaults(ksp.k);
}

// A Krylov solve that did not converge stops the run with PETSc's reason (EXIT_NOT_CONVERGED):
// every rank sees the same reason, so every rank throws the same error.
void Engine::ksp_check(KSP ksp, const std::string& what) const {
  KSPConvergedReason reason;
  PetscInt its;
  HC_PETSC(KSPGetConvergedReason(ksp, &reason));
  HC_PETSC(KSPGetIterationNumber(ksp, &its));
  if (reason < 0)
    throw Error(what + ": CG did not converge: " + KSPConvergedReasons[reason] + " after " + std::to_string(its) +
                    " iterations (solver.petsc.ksp_max_it = " + std::to_string(opt.petsc.ksp_max_it) +
                    ", ksp_rtol = " + short_number(opt.petsc.ksp_rtol) + ", pc = " + opt.petsc.pc + ")",
                EXIT_NOT_CONVERGED);
}

// K z = f with CG + the full-size preconditioner: the unconstrained elastic solution sets U_s.
void Engine::elastic_solve() {
  const auto t0 = clk::now();
  PKsp ksp;
  create_cg(ksp, "elastic_");
  HC_PETSC(KSPSetOperators(ksp.k, K.m, K.m));
  HC_PETSC(KSPSolve(ksp.k, f.v, zfree.v));
  ksp_check(ksp.k, "elastic solve K z = f");
  PetscInt its;
  HC_PETSC(KSPGetIterationNumber(ksp.k, &its));
  rep.json["elastic_krylov_iterations"] = its;
  PetscReal zmax, fmax;
  HC_PETSC(VecNorm(zfree.v, NORM_INFINITY, &zmax));
  HC_PETSC(VecNorm(f.v, NORM_INFINITY, &fmax));
  U_s = zmax > 0 ? zmax : 1.0;
  F_s = fmax > 0 ? fmax : 1.0;
  timings["linear_elastic_solve"] = since(t0);
  log_info() << "petsc: elastic solve, CG + " << opt.petsc.pc << ": " << its << " iterations, "
             << timings["linear_elastic_solve"] << " s";
}

// Π_λ,ε at x = U_s zs, in the cholmod engine's units: value / (F_s U_s), gradient / F_s.
double Engine::energy(::Vec z, ::Vec g) {
  HC_PETSC(VecCopy(z, work.v));
  HC_PETSC(VecScale(work.v, U_s));
  HC_PETSC(MatMult(K.m, work.v, g));  // g = K x
  PetscScalar xKx, fx;
  HC_PETSC(VecDot(work.v, g, &xKx));
  HC_PETSC(VecDot(work.v, f.v, &fx));
  HC_PETSC(VecAXPY(g, -1.0, f.v));  // g = K x − f
  double local = 0;
  const PetscScalar* px;
  PetscScalar* pg;
  HC_PETSC(VecGetArrayRead(work.v, &px));
  HC_PETSC(VecGetArray(g, &pg));
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    const Index k = my_nodes[q];
    const Index i = cdof(k) - lo;
    const double w = md.contact.w[k];
    if (law) {
      local += w * law->j(px[i]);
      pg[i] += w * law->p(px[i]);
    }
    if (md.friction && lambda[q] > 0) {
      Eigen::Vector2d t = Eigen::Vector2d::Zero();
      for (int c = 1; c < d; ++c) t[c - 1] = px[i + c];
      const double y = t.norm();
      local += w * lambda[q] * f0(y, eps_tau);
      const double s = w * lambda[q] * f1_over_y(y, eps_tau);
      for (int c = 1; c < d; ++c) pg[i + c] += s * t[c - 1];
    }
  }
  HC_PETSC(VecRestoreArrayRead(work.v, &px));
  HC_PETSC(VecRestoreArray(g, &pg));
  HC_PETSC(VecScale(g, 1.0 / F_s));
  const double value = 0.5 * xKx - fx + allreduce_sum(local, comm);
  return value / (F_s * U_s);
}

// H = (K + Σ nodal blocks) U_s / F_s. The normal block is w max(p_ε′, 0): the softening branch
// (c2 < 0) is clamped as the newton backend's Psd::CLAMP does, so that CG sees a positive
// semidefinite Hessian; friction's block w λ ∇²f0 is positive semidefinite as it is (smooth_norm.hpp).
void Engine::hessian(::Vec z, ::Mat H) {
  HC_PETSC(MatCopy(K.m, H, SAME_NONZERO_PATTERN));
  const PetscScalar* pz;
  HC_PETSC(VecGetArrayRead(z, &pz));
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    const Index k = my_nodes[q];
    const PetscInt i0 = cdof(k);
    const double w = md.contact.w[k];
    double B[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    if (law) B[0] = w * std::max(0.0, law->dp(U_s * pz[i0 - lo]));
    if (md.friction && lambda[q] > 0) {
      if (d == 2) {
        const double y = std::abs(U_s * pz[i0 - lo + 1]);
        B[3] = w * lambda[q] * df1(y, eps_tau);
      } else {
        const Eigen::Vector2d t(U_s * pz[i0 - lo + 1], U_s * pz[i0 - lo + 2]);
        const Eigen::Matrix2d Ht = w * lambda[q] * smooth_norm_hessian(t, eps_tau);
        B[4] = Ht(0, 0), B[5] = Ht(0, 1), B[7] = Ht(1, 0), B[8] = Ht(1, 1);
      }
    }
    PetscInt idx[3] = {i0, i0 + 1, i0 + 2};
    HC_PETSC(MatSetValues(H, d, idx, d, idx, B, ADD_VALUES));
  }
  HC_PETSC(VecRestoreArrayRead(z, &pz));
  HC_PETSC(MatAssemblyBegin(H, MAT_FINAL_ASSEMBLY));
  HC_PETSC(MatAssemblyEnd(H, MAT_FINAL_ASSEMBLY));
  HC_PETSC(MatScale(H, U_s / F_s));
}

PetscErrorCode Engine::tao_objgrad(Tao, ::Vec x, PetscReal* fval, ::Vec g, void* ctx) {
  try {
    *fval = static_cast<Engine*>(ctx)->energy(x, g);
    return 0;
  } catch (const std::exception& e) {
    log_warn() << "petsc: objective: " << e.what();
    return PETSC_ERR_LIB;
  }
}

PetscErrorCode Engine::tao_hessian(Tao, ::Vec x, ::Mat H, ::Mat, void* ctx) {
  try {
    static_cast<Engine*>(ctx)->hessian(x, H);
    return 0;
  } catch (const std::exception& e) {
    log_warn() << "petsc: Hessian: " << e.what();
    return PETSC_ERR_LIB;
  }
}

// The backends' first-order residual (nlp/backend.hpp's, on this rank's rows), max over ranks:
// max_i min(|g_i|, room towards the bound that −g_i points to), in scaled units; @p lo_s, @p up_s
// are the scaled bounds (scaled_bound), ±PETSC_INFINITY where there is none.
double Engine::first_order_residual(::Vec z, ::Vec g, ::Vec lo_s, ::Vec up_s) const {
  const PetscScalar *pz, *pg, *pl, *pu;
  HC_PETSC(VecGetArrayRead(z, &pz));
  HC_PETSC(VecGetArrayRead(g, &pg));
  HC_PETSC(VecGetArrayRead(lo_s, &pl));
  HC_PETSC(VecGetArrayRead(up_s, &pu));
  const Index nloc = hi - lo;
  const double r = hemicontact::first_order_residual(Eigen::Map<const Vec>(pz, nloc), Eigen::Map<const Vec>(pg, nloc),
                                                     Eigen::Map<const Vec>(pl, nloc), Eigen::Map<const Vec>(pu, nloc));
  HC_PETSC(VecRestoreArrayRead(z, &pz));
  HC_PETSC(VecRestoreArrayRead(g, &pg));
  HC_PETSC(VecRestoreArrayRead(lo_s, &pl));
  HC_PETSC(VecRestoreArrayRead(up_s, &pu));
  return allreduce_max(r, comm);
}

void Engine::scaled_bound(::Vec b, ::Vec out) const {
  const PetscScalar* pb;
  PetscScalar* po;
  HC_PETSC(VecGetArrayRead(b, &pb));
  HC_PETSC(VecGetArray(out, &po));
  for (PetscInt i = 0; i < hi - lo; ++i)
    po[i] = (pb[i] >= PETSC_INFINITY || pb[i] <= PETSC_NINFINITY) ? pb[i] : pb[i] / U_s;
  HC_PETSC(VecRestoreArrayRead(b, &pb));
  HC_PETSC(VecRestoreArray(out, &po));
}

Eigen::VectorXd Engine::gather(::Vec v) const {
  VecScatter sc;
  ::Vec all;
  HC_PETSC(VecScatterCreateToAll(v, &sc, &all));
  HC_PETSC(VecScatterBegin(sc, v, all, INSERT_VALUES, SCATTER_FORWARD));
  HC_PETSC(VecScatterEnd(sc, v, all, INSERT_VALUES, SCATTER_FORWARD));
  Eigen::VectorXd out(n);
  const PetscScalar* p;
  HC_PETSC(VecGetArrayRead(all, &p));
  if (perm.empty())
    std::copy(p, p + n, out.data());
  else
    for (PetscInt x = 0; x < n; ++x) out[x] = p[perm[static_cast<size_t>(x)]];
  HC_PETSC(VecRestoreArrayRead(all, &p));
  VecScatterDestroy(&sc);
  VecDestroy(&all);
  return out;
}

Eigen::VectorXd Engine::local_gamma3(::Vec z) const {
  Eigen::VectorXd c(static_cast<Index>(my_nodes.size()) * d);
  const PetscScalar* p;
  VecGetArrayRead(z, &p);
  for (size_t q = 0; q < my_nodes.size(); ++q)
    for (int a = 0; a < d; ++a) c[static_cast<Index>(q) * d + a] = p[cdof(my_nodes[q]) + a - lo];
  VecRestoreArrayRead(z, &p);
  return c;
}

// One TAO bounded-Newton run from the current zs (warm start), with λ and ε frozen.
OuterIteration Engine::minimize(size_t stage) {
  OuterIteration rec;
  rec.k = k_total++;
  rec.stage = static_cast<int>(stage);
  rec.eps_tau = eps_tau;
  rec.eps_nu = eps_nu;
  const auto t0 = clk::now();
  PTao tao;
  PMat H;
  PVec lo_s, up_s;
  HC_PETSC(MatDuplicate(K.m, MAT_DO_NOT_COPY_VALUES, &H.m));
  HC_PETSC(VecDuplicate(lower.v, &lo_s.v));
  HC_PETSC(VecDuplicate(upper.v, &up_s.v));
  scaled_bound(lower.v, lo_s.v);
  scaled_bound(upper.v, up_s.v);
  HC_PETSC(TaoCreate(comm, &tao.t));
  HC_PETSC(TaoSetType(tao.t, tao_type(opt.backend).c_str()));
  HC_PETSC(TaoSetSolution(tao.t, zs.v));
  HC_PETSC(TaoSetObjectiveAndGradient(tao.t, grad.v, &Engine::tao_objgrad, this));
  HC_PETSC(TaoSetHessian(tao.t, H.m, H.m, &Engine::tao_hessian, this));
  HC_PETSC(TaoSetVariableBounds(tao.t, lo_s.v, up_s.v));
  // Converged when the projected gradient (scaled units, as every backend's solver.tol) is ≤ tol.
  HC_PETSC(TaoSetTolerances(tao.t, opt.backend_options.tol, 0.0, 0.0));
  HC_PETSC(TaoSetMaximumIterations(tao.t, opt.backend_options.max_iter));
  HC_PETSC(TaoSetMaximumFunctionEvaluations(tao.t, 100 * opt.backend_options.max_iter));
  KSP ksp;
  HC_PETSC(TaoGetKSP(tao.t, &ksp));
  if (ksp) {
    set_pc(ksp, opt.petsc.newton_pc);
    HC_PETSC(KSPSetTolerances(ksp, opt.petsc.ksp_rtol, PETSC_DEFAULT, PETSC_DEFAULT, opt.petsc.ksp_max_it));
  }
  HC_PETSC(TaoSetFromOptions(tao.t));
  HC_PETSC(TaoGetKSP(tao.t, &ksp));
  if (ksp) {
    hypre_defaults(ksp);
    if (opt.petsc.newton_pc == "gamg") fresh_gamg(ksp);
  }
  HC_PETSC(TaoSolve(tao.t));
  TaoConvergedReason reason;
  PetscInt its, lits, nfev;
  HC_PETSC(TaoGetConvergedReason(tao.t, &reason));
  HC_PETSC(TaoGetIterationNumber(tao.t, &its));
  HC_PETSC(TaoGetLinearSolveIterations(tao.t, &lits));
  HC_PETSC(TaoGetCurrentFunctionEvaluations(tao.t, &nfev));
  newton_total += its;
  krylov_total += lits;
  // The same first-order residual every backend reports, at the returned point.
  const double fval = energy(zs.v, grad.v);
  const double kkt = first_order_residual(zs.v, grad.v, lo_s.v, up_s.v);
  rec.backend.iterations = static_cast<int>(its);
  rec.backend.evaluations = static_cast<int>(nfev);
  rec.backend.f = fval;
  rec.backend.kkt_norm = kkt;
  rec.backend.seconds = since(t0);
  rec.backend.message = std::string("TAO ") + TaoConvergedReasons[reason] + ", " + std::to_string(lits) +
                        " Krylov iterations";
  if (reason > 0)
    rec.backend.status = SolveStatus::CONVERGED;
  else if (reason == TAO_DIVERGED_MAXITS)
    rec.backend.status = SolveStatus::MAX_ITERATIONS;
  else if (kkt <= opt.petsc.acceptable_tol)
    rec.backend.status = SolveStatus::ACCEPTABLE;  // a line search stopped at round-off
  else
    rec.backend.status = SolveStatus::FAILED;
  stages.push_back({{"k", rec.k}, {"stage", rec.stage}, {"newton", its}, {"krylov", lits},
                    {"krylov_per_newton", its > 0 ? double(lits) / double(its) : 0.0}, {"tao_reason", TaoConvergedReasons[reason]},
                    {"seconds", rec.backend.seconds}});
  const Eigen::VectorXd c = local_gamma3(zs.v);
  double dmax = 0, smax = 0;
  if (c.size()) {
    dmax = (c - prev_c).cwiseAbs().maxCoeff();
    smax = std::max(c.cwiseAbs().maxCoeff(), prev_c.cwiseAbs().maxCoeff());
  }
  dmax = allreduce_max(dmax, comm);
  smax = allreduce_max(smax, comm);
  rec.change_u = smax > 0 ? dmax / smax : 0.0;
  prev_c = c;
  rec.grad_norm = kkt;
  return rec;
}

// λ ← (1−θ)λ + θ F_b(u_ν) on the owned Γ3 nodes (driver/solve.cpp's relax_lambda).
void Engine::relax_lambda(OuterIteration& rec, bool measure_contraction, double& prev_delta) {
  const PetscScalar* p;
  VecGetArrayRead(zs.v, &p);
  double dmax = 0, lmax = 0;
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    const double fb = md.friction->F(U_s * p[cdof(my_nodes[q]) - lo]);
    const double l = (1 - opt.relaxation) * lambda[q] + opt.relaxation * fb;
    dmax = std::max(dmax, std::abs(l - lambda[q]));
    lmax = std::max({lmax, std::abs(l), std::abs(lambda[q])});
    lambda[q] = l;
  }
  VecRestoreArrayRead(zs.v, &p);
  dmax = allreduce_max(dmax, comm);
  lmax = allreduce_max(lmax, comm);
  rec.change_lambda = lmax > 0 ? dmax / lmax : 0.0;
  rec.delta_lambda = dmax;
  const double noise = opt.contraction_floor * lmax;
  if (measure_contraction && prev_delta > noise && dmax > noise) rec.contraction = dmax / prev_delta;
  prev_delta = dmax;
}

// One continuation stage, as driver/solve.cpp's run_stage: one lagged update on a coarse stage,
// the fixed point λ = F_b(u_ν) at the final one. @return false when TAO failed.
bool Engine::run_stage(size_t stage) {
  eps_tau = schedule[stage].first * U_s;
  eps_nu = schedule[stage].second * U_s;
  if (md.normal_law) law = std::make_unique<MollifiedLaw>(md.normal_law, eps_nu, "solver.eps_nu");
  const bool final_stage = stage + 1 == schedule.size();
  double prev_change = INF, prev_delta = INF;
  int slow = 0;
  for (int it = 0;; ++it) {
    OuterIteration rec = minimize(stage);
    if (lagged) relax_lambda(rec, final_stage && it > 0, prev_delta);
    sol.history.push_back(rec);
    log_info() << "outer " << rec.k << " (stage " << stage << ", eps " << short_number(schedule[stage].first)
               << "): " << tao_type(opt.backend) << " " << to_string(rec.backend.status) << " in "
               << rec.backend.iterations << " Newton it (" << rec.backend.message << "), "
               << short_number(rec.backend.seconds) << " s; |dx_G3|/|x_G3| = " << short_number(rec.change_u)
               << ", |dlambda|/|lambda| = " << short_number(rec.change_lambda) << ", first-order residual "
               << short_number(rec.grad_norm);
    if (!rec.backend.ok()) {
      sol.backend_ok = false;
      sol.message = "backend tao:" + tao_type(opt.backend) + " failed at outer iteration " + std::to_string(rec.k) +
                    ": " + to_string(rec.backend.status) + " (" + rec.backend.message + ")";
      return false;
    }
    if (!lagged || !final_stage) return true;
    const double change = std::max(rec.change_u, rec.change_lambda);
    if (it > 0 && change <= opt.tol_u) return true;
    if (it + 1 >= opt.max_outer) {
      sol.fixed_point_converged = false;
      sol.message = "fixed point lambda = F_b(u_nu) did not converge in " + std::to_string(opt.max_outer) +
                    " outer iterations (last change " + short_number(change) +
                    "); raise solver.fixed_point.max_iters or lower solver.fixed_point.relaxation";
      return true;
    }
    slow = (change > opt.stall_ratio * prev_change) ? slow + 1 : 0;
    prev_change = change;
    if (slow >= opt.stall_iters) {
      sol.fixed_point_converged = false;
      sol.message = "fixed point lambda = F_b(u_nu) does not contract: the change (" + short_number(change) +
                    ") has not decreased for " + std::to_string(opt.stall_iters) +
                    " outer iterations; try a smaller solver.fixed_point.relaxation";
      return true;
    }
  }
}

bool Engine::settled() const {
  if (!(opt.certify_below > 0) || !opt.polish || !sol.fixed_point_converged || !sol.backend_ok || sol.history.empty())
    return false;
  const OuterIteration& last = sol.history.back();
  return last.change_u <= opt.certify_below && (!lagged || last.change_lambda <= opt.certify_below);
}

Solution Engine::evaluate(const Eigen::VectorXd& x, const SolveOptions& o) const {
  Solution s;
  s.x = x;
  s.u = md.dofs.to_full(x);
  evaluate_solution(md, o, s);
  return s;
}

// The exact polish in the full space (driver/polish.hpp's status system, without condensation):
// with the statuses of @p s0 fixed, Newton's method on
//   interior rows:     (K x − f)_i = 0
//   contact:           x_ν = g                              (eq. (5): the rigid part takes the rest)
//   compliance/sep.:   (K x − f)_ν + w p(x_ν) = 0           (p affine on the node's branch, eq. (32))
//   stick:             x_τ = 0;   frictionless:  (K x − f)_τ = 0
//   slip:              (K x − f)_τ + w λ t = 0,  t = x_τ/|x_τ|,  λ = F_b(x_ν)   (eq. (6))
// λ is evaluated at the current iterate and held in the Jacobian (K + w p′ + w λ (I − t tᵀ)/|x_τ|,
// symmetric, so CG + GAMG apply); the iteration then converges linearly in λ with the fixed point's
// contraction, and stops when the step reaches round-off (1e-14 relative) or stops decreasing.
// Fixed unknowns (contact ν, stick τ, rollers) are eliminated with MatZeroRowsColumns.
PolishResult Engine::polish(Eigen::VectorXd& x_io, const SolveOptions& read_opt, const Solution& s0_user) {
  PolishResult r;
  r.attempted = true;
  r.before = s0_user.certificate.max_residual;
  const Solution s0 = read_opt.status_tol == opt.status_tol ? s0_user : evaluate(x_io, read_opt);
  const double delta = 1e-7 * s0.certificate.length_scale;
  PVec x, R, dx;
  PMat J;
  PKsp ksp;
  HC_PETSC(VecDuplicate(f.v, &x.v));
  HC_PETSC(VecDuplicate(f.v, &R.v));
  HC_PETSC(VecDuplicate(f.v, &dx.v));
  HC_PETSC(MatDuplicate(K.m, MAT_DO_NOT_COPY_VALUES, &J.m));
  HC_PETSC(MatSetNearNullSpace(J.m, rigid));
  create_cg(ksp, "polish_");
  // The start: the smoothed answer with the fixed unknowns set to their values.
  std::vector<PetscInt> fixed;
  {
    PetscScalar* px;
    HC_PETSC(VecGetArray(x.v, &px));
    for (PetscInt l = 0; l < hi - lo; ++l) px[l] = x_io[X(l)];
    for (Index k : my_nodes) {
      const PetscInt iv = cdof(k);
      const NodeStatus st = s0.status[k];
      if (st.normal == NormalStatus::CONTACT) px[iv - lo] = md.contact.g[k], fixed.push_back(iv);
      const bool frictionless = frictionless_at(md, s0.state.u_nu[k], delta);
      for (int c = 1; c < d; ++c)
        if (roller_fixed(md, k, c) || (!frictionless && st.tangential == TangentialStatus::STICK))
          px[iv + c - lo] = 0, fixed.push_back(iv + c);
    }
    HC_PETSC(VecRestoreArray(x.v, &px));
  }
  bool bad = false;
  double prev = INF;
  std::string note;
  for (r.iterations = 1; r.iterations <= opt.petsc.polish_max_iters; ++r.iterations) {
    HC_PETSC(MatMult(K.m, x.v, R.v));
    HC_PETSC(VecAXPY(R.v, -1.0, f.v));
    HC_PETSC(MatCopy(K.m, J.m, SAME_NONZERO_PATTERN));
    const PetscScalar* px;
    PetscScalar* pr;
    HC_PETSC(VecGetArrayRead(x.v, &px));
    HC_PETSC(VecGetArray(R.v, &pr));
    int local_bad = 0;
    for (Index k : my_nodes) {
      const PetscInt iv = cdof(k);
      const double w = md.contact.w[k], xn = px[iv - lo];
      const NodeStatus st = s0.status[k];
      double B[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
      if (st.normal != NormalStatus::CONTACT && md.normal_law) {
        pr[iv - lo] += w * md.normal_law->p(xn);
        B[0] = w * md.normal_law->dp(xn);
      }
      const bool frictionless = frictionless_at(md, s0.state.u_nu[k], delta);
      if (!frictionless && st.tangential != TangentialStatus::STICK) {
        Eigen::Vector2d t = Eigen::Vector2d::Zero();
        for (int c = 1; c < d; ++c) t[c - 1] = px[iv + c - lo];
        const double y = t.norm();
        if (!(y > 0)) {
          local_bad = 1;  // a slipping node reached u_τ = 0: its status is wrong
          continue;
        }
        t /= y;
        const double lam = md.friction->F(xn);
        for (int c = 1; c < d; ++c) pr[iv + c - lo] += w * lam * t[c - 1];
        if (d == 3) {
          const Eigen::Matrix2d Jt = w * lam / y * (Eigen::Matrix2d::Identity() - t * t.transpose());
          B[4] = Jt(0, 0), B[5] = Jt(0, 1), B[7] = Jt(1, 0), B[8] = Jt(1, 1);
        }
      }
      PetscInt idx[3] = {iv, iv + 1, iv + 2};
      HC_PETSC(MatSetValues(J.m, d, idx, d, idx, B, ADD_VALUES));
    }
    for (PetscInt i : fixed) pr[i - lo] = 0;  // fixed unknowns keep their value: δ = 0 there
    HC_PETSC(VecRestoreArrayRead(x.v, &px));
    HC_PETSC(VecRestoreArray(R.v, &pr));
    HC_PETSC(MatAssemblyBegin(J.m, MAT_FINAL_ASSEMBLY));
    HC_PETSC(MatAssemblyEnd(J.m, MAT_FINAL_ASSEMBLY));
    if (allreduce_max(local_bad, comm) > 0) {
      bad = true;
      note = "a slipping node reached u_tau = 0";
      break;
    }
    HC_PETSC(MatZeroRowsColumns(J.m, static_cast<PetscInt>(fixed.size()), fixed.data(), 1.0, nullptr, nullptr));
    HC_PETSC(VecScale(R.v, -1.0));
    HC_PETSC(KSPSetOperators(ksp.k, J.m, J.m));
    HC_PETSC(KSPSolve(ksp.k, R.v, dx.v));
    KSPConvergedReason reason;
    PetscInt its;
    HC_PETSC(KSPGetConvergedReason(ksp.k, &reason));
    HC_PETSC(KSPGetIterationNumber(ksp.k, &its));
    polish_krylov += its;
    ++polish_newton;
    if (reason < 0) {
      bad = true;
      note = std::string("CG on the status system: ") + KSPConvergedReasons[reason];
      break;
    }
    HC_PETSC(VecAXPY(x.v, 1.0, dx.v));
    PetscReal change, scale;
    HC_PETSC(VecNorm(dx.v, NORM_INFINITY, &change));
    HC_PETSC(VecNorm(x.v, NORM_INFINITY, &scale));
    if (!(change > 1e-14 * scale) || (r.iterations > 2 && change >= prev)) break;
    prev = change;
  }
  if (bad) {
    r.note = note;
    return r;
  }
  // Keep the candidate only if the statuses stay and the certificate does not get worse
  // (driver/polish.cpp's accept_if_better, the same rule).
  const Eigen::VectorXd xc = gather(x.v);
  if (!xc.allFinite()) {
    r.note = "singular status system";
    return r;
  }
  const Solution s1 = evaluate(xc, opt);
  r.after = s1.certificate.max_residual;
  for (Index k = 0; k < md.contact.size(); ++k)
    if (s1.status[k].normal != s0.status[k].normal ||
        (s1.status[k].tangential != s0.status[k].tangential && !frictionless_at(md, s0.state.u_nu[k], delta))) {
      r.note = "statuses changed at node " + std::to_string(k) + " (" + s0.status[k].str() + " -> " +
               s1.status[k].str() + ")";
      return r;
    }
  if (!(r.after <= std::max(r.before, 1e-12))) {
    r.note = "the certificate did not improve";
    return r;
  }
  r.accepted = true;
  x_io = xc;
  return r;
}

// The statuses read at check.status_tol and, when the stage's ε is larger, at 10 ε (a sticking
// node shows |u_τ| ~ ε U): driver/polish.cpp's first two readings.
PolishResult Engine::polish_with_readings(Eigen::VectorXd& x, size_t stage) {
  const auto t0 = clk::now();
  const Solution s0 = evaluate(x, opt);
  PolishResult r = polish(x, opt, s0);
  const double coarse = 10 * std::max(schedule[stage].first, schedule[stage].second);
  if (!r.accepted && coarse > opt.status_tol) {
    SolveOptions o = opt;
    o.status_tol = coarse;
    PolishResult r2 = polish(x, o, s0);
    r2.iterations += r.iterations;
    if (r2.accepted) r2.note = "statuses read at 10 eps";
    else r2.note = r.note + "; at 10 eps: " + r2.note;
    r = r2;
  }
  timings["polish"] += since(t0);
  return r;
}

void Engine::finish(Solution& s, Eigen::VectorXd x, clk::time_point t0) {
  const auto t1 = clk::now();
  s.x = std::move(x);
  s.u = md.dofs.to_full(s.x);
  // Every minimization here is the named (or auto-chosen) backend's own: it ran when one is recorded.
  for (auto& h : s.history) h.solver = s.backend;
  s.backend_use.requested = opt.backend;
  s.backend_use.ran = !s.history.empty();
  if (!s.backend_use.ran) s.backend_use.not_run = "linear elasticity without contact: one CG solve is the answer";
  evaluate_solution(md, opt, s);
  timings["certificate"] = since(t1);
  double nlp = 0;
  for (const auto& h : s.history) nlp += h.backend.seconds;
  timings["backend"] = nlp;
  timings["solve_total"] = since(t0);
  for (const auto& [key, v] : timings) s.timings[key] = v;
  if (!s.backend_ok && s.certificate.passed)
    s.message += "; the certificate passed all the same (max residual " + short_number(s.certificate.max_residual) +
                 "), so the answer is accepted";
  if (s.message.empty())
    s.message = s.certificate.passed ? "converged; certificate passed"
                                     : "converged, but the certificate failed (max residual " +
                                           short_number(s.certificate.max_residual) + ")";
  // The report's record of the engine.
  const long rss = peak_rss_kb();
  long rss_sum = 0, rss_max = 0;
  MPI_Allreduce(&rss, &rss_sum, 1, MPI_LONG, MPI_SUM, comm);
  MPI_Allreduce(&rss, &rss_max, 1, MPI_LONG, MPI_MAX, comm);
  MatInfo info;
  HC_PETSC(MatGetInfo(K.m, MAT_GLOBAL_SUM, &info));
  rep.json["nonzeros_per_row"] = n > 0 ? info.nz_used / double(n) : 0.0;
  rep.json["ranks"] = size;
  rep.json["block_size"] = bs;
  rep.json["unknowns"] = n;
  rep.json["method"] = tao_type(opt.backend) == "ssn" ? std::string("ssn") : "tao:" + tao_type(opt.backend);
  rep.json["newton_pc"] = opt.petsc.newton_pc;
  rep.json["pc"] = opt.petsc.pc;
  rep.json["newton_iterations"] = newton_total;
  rep.json["krylov_iterations"] = krylov_total;
  rep.json["krylov_per_newton"] = newton_total > 0 ? double(krylov_total) / double(newton_total) : 0.0;
  rep.json["polish_newton_iterations"] = polish_newton;
  rep.json["polish_krylov_iterations"] = polish_krylov;
  rep.json["minimizations"] = stages;
  rep.json["peak_rss_mb_sum"] = double(rss_sum) / 1024.0;
  rep.json["peak_rss_mb_max"] = double(rss_max) / 1024.0;
  rep.json["bytes_per_dof"] = n > 0 ? double(rss_sum) * 1024.0 / double(n) : 0.0;
}

Engine::BandRows Engine::save_band() const {
  std::vector<char> on_gamma3(static_cast<size_t>(n), 0);
  for (Index k = 0; k < md.contact.size(); ++k)
    for (int c = 0; c < d; ++c) on_gamma3[static_cast<size_t>(cdof(k) + c)] = 1;
  BandRows b;
  b.start.push_back(0);
  for (PetscInt i = lo; i < hi; ++i) {
    PetscInt nc;
    const PetscInt* cols;
    const PetscScalar* vals;
    HC_PETSC(MatGetRow(K.m, i, &nc, &cols, &vals));
    if (std::any_of(cols, cols + nc, [&](PetscInt j) { return on_gamma3[static_cast<size_t>(j)] != 0; })) {
      b.rows.push_back(i);
      b.cols.insert(b.cols.end(), cols, cols + nc);
      b.vals.insert(b.vals.end(), vals, vals + nc);
      b.start.push_back(static_cast<PetscInt>(b.cols.size()));
    }
    HC_PETSC(MatRestoreRow(K.m, i, &nc, &cols, &vals));
  }
  return b;
}

// The same values written back over the same places (INSERT_VALUES): K is bitwise as assembled.
void Engine::restore_band(const BandRows& b) const {
  for (size_t r = 0; r < b.rows.size(); ++r) {
    const PetscInt s0 = b.start[r], nc = b.start[r + 1] - s0;
    HC_PETSC(MatSetValues(K.m, 1, &b.rows[r], nc, b.cols.data() + s0, b.vals.data() + s0, INSERT_VALUES));
  }
  HC_PETSC(MatAssemblyBegin(K.m, MAT_FINAL_ASSEMBLY));
  HC_PETSC(MatAssemblyEnd(K.m, MAT_FINAL_ASSEMBLY));
}

// Backend "ssn": a semismooth (active-set) Newton method on the unsmoothed conditions of (22) in
// the full space, every status read again at every step from the current iterate x and the
// residual R = K x − f (the complementarity functions of the primal-dual active-set method, with
// c_n, c_t = the node's diagonal of K so that forces and displacements compare in one unit):
//   normal:  contact  iff  −(R_ν + w p(x_ν)) + c_n (x_ν − g) > 0          (eq. (5): u_ν ≤ g)
//            then x_ν = g; else R_ν + w p(x_ν) = 0 on x_ν's branch of p      (eq. (32))
//   tangent: stick    iff  |y| ≤ w λ,  y = −R_τ + c_t x_τ,  λ = F_b(x_ν)     (eq. (6))
//            then x_τ = 0; else R_τ + w λ t = 0 with t = y/|y|
// Each step solves the linearization with the fixed unknowns eliminated (MatZeroRowsColumns, so
// the matrix stays symmetric positive definite and CG + GAMG (solver.petsc.near_null_space) apply):
// J = K + w p′ (branch slope) + w λ (I − t tᵀ)/ρ on sliding nodes, ρ = max(|x_τ|, (|y| − wλ)/c_t)
// (= |x_τ| at a solution; positive where x_τ is still 0). λ is held in J: the coupling through
// F_b(u_ν) converges linearly, as the outer fixed point does, without an outer loop. No smoothing
// and no continuation: the answer is judged by the same certificate. The nonlinearity lives on Γ3
// only, so the AMG hierarchy built for the first step serves later ones (solver.petsc.pc_rebuild).
Solution Engine::run_ssn(clk::time_point t0) {
  sol.backend = std::string("ssn (semismooth Newton, CG + ") + opt.petsc.pc + ", PETSc, " + std::to_string(size) +
                " rank" + (size > 1 ? "s" : "") + ")";
  sol.formulation = "full";
  sol.fixed_point_converged = true;
  sol.skipped.push_back("continuation: ssn solves the unsmoothed problem (no eps stages)");
  if (opt.smallness)
    sol.skipped.push_back("smallness: (21) is evaluated by the cholmod engine only (it needs a factorization)");
  if (!md.normal_law) sol.skipped.push_back("normal_compliance: no soft layer (contact.normal_law.type = none)");
  if (!md.friction) sol.skipped.push_back("friction: frictionless (contact.friction.type = none)");
  if (md.friction && md.friction->depends_on_u_nu())
    sol.skipped.push_back("fixed_point: lambda = F_b(u_nu) is read at every Newton step (no outer loop)");
  if (md.gap.is_infinite()) sol.skipped.push_back("bounds: no rigid obstacle (g = inf)");
  sol.skipped.push_back("polish: ssn's steps are the polish's, with statuses updated");

  PVec x, R, dx, rhs, fixv, diagK;
  PKsp ksp;
  for (PVec* v : {&x, &R, &dx, &rhs, &fixv, &diagK}) HC_PETSC(VecDuplicate(f.v, &v->v));
  HC_PETSC(MatGetDiagonal(K.m, diagK.v));
  // No second matrix: each step's J is K itself, changed in place (Γ3 blocks added, fixed rows and
  // columns zeroed) and put back from the saved rows before K is read again. A copy of K would cost
  // ~0.5 KB per unknown (44 nonzeros per row in 3D), a quarter of the engine's memory target (2 KB
  // per unknown).
  const BandRows band = save_band();
  HC_PETSC(MatSetOption(K.m, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
  HC_PETSC(MatSetOption(K.m, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
  ::Mat& J = K.m;
  // rtol on the true residual: the inexact-Newton forcing terms and the hierarchy's quality
  // (iterations per decade) then mean what they say.
  create_cg(ksp, "ssn_", KSP_NORM_UNPRECONDITIONED);
  HC_PETSC(VecSet(x.v, 0.0));
  // A fixed unknown's row keeps a diagonal of K's own size (the mean K_ii), not 1 against
  // K_ii ~ E h: its eigenvalue then lies inside K's spectrum, where the Chebyshev smoothers' bounds
  // and CG's convergence do not see it as an outlier.
  PetscReal diag_sum;
  HC_PETSC(VecNorm(diagK.v, NORM_1, &diag_sum));
  const double diag_scale = n > 0 && diag_sum > 0 ? diag_sum / static_cast<double>(n) : 1.0;
  PetscReal fmax;
  HC_PETSC(VecNorm(f.v, NORM_INFINITY, &fmax));
  F_s = fmax > 0 ? fmax : 1.0;

  // Status per owned Γ3 node: bit 0 contact, bit 1 stick, bits 2.. the branch of p (its index + 1).
  std::vector<int> status(my_nodes.size(), -1), prev_status(my_nodes.size(), -2);
  // The slip direction t each sliding node was given this step (0: not sliding).
  std::vector<Eigen::Vector2d> slip_dir(my_nodes.size(), Eigen::Vector2d::Zero());
  // A node whose slip reversed in the last step: held at stick for one step (below).
  std::vector<char> hold_stick(my_nodes.size(), 0);
  std::vector<PetscInt> fixed;
  nlohmann::json steps = nlohmann::json::array();
  // CG iterations per decade that the hierarchy is judged against: the larger of the step that
  // built it and the first step that reused it. The build step alone is no fair reference: the
  // first one has every Γ3 node fixed, an easier matrix than any later step's (70³: 4 per decade
  // against 7 at the next step, whatever the hierarchy), so it called for rebuilds that did not
  // lower the counts (70³, 2 ranks: 2 builds 169 CG iterations, 1 build 155).
  double built_per_decade = 0;
  bool reference_pending = false;
  bool rebuild = true, converged = false;
  int unchanged = 0;
  double prev_step = INF;
  const auto t_loop = clk::now();
  int k = 0;
  for (k = 1; k <= opt.petsc.ssn_max_iters; ++k) {
    if (k > 1) restore_band(band);  // K again: the last step's J changed it
    HC_PETSC(MatMult(K.m, x.v, R.v));
    HC_PETSC(VecAXPY(R.v, -1.0, f.v));
    HC_PETSC(VecSet(fixv.v, 0.0));
    fixed.clear();
    const PetscScalar *px, *pd;
    PetscScalar *pr, *pf;
    HC_PETSC(VecGetArrayRead(x.v, &px));
    HC_PETSC(VecGetArrayRead(diagK.v, &pd));
    HC_PETSC(VecGetArray(R.v, &pr));
    HC_PETSC(VecGetArray(fixv.v, &pf));
    long changed = 0;
    for (size_t q = 0; q < my_nodes.size(); ++q) {
      const Index kk = my_nodes[q];
      const PetscInt iv = cdof(kk);
      const PetscInt l = iv - lo;
      const double w = md.contact.w[kk], xn = px[l], g = md.contact.g[kk];
      slip_dir[q].setZero();  // set below if the node slides this step
      double B[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
      int st = 0;
      const double p = md.normal_law ? md.normal_law->p(xn) : 0.0;
      // The first step starts from every node in contact (x = 0 has no reaction to read): the free
      // elastic solve it would otherwise make pushes Γ3 far through g and every status changes
      // twice. 3D scene, 2 ranks: 70³ 13 → 11 steps, 178 → 115 CG iterations, 62.9 → 55.9 s.
      const bool contact = std::isfinite(g) && (k == 1 || -(pr[l] + w * p) + pd[l] * (xn - g) > 0);
      if (contact) {
        st |= 1;
        fixed.push_back(iv);
        pf[l] = g - xn;
      } else {
        pr[l] += w * p;
        if (md.normal_law) B[0] = w * md.normal_law->dp(xn);
      }
      const double lam = md.friction ? md.friction->F(xn) : 0.0;
      Eigen::Vector2d xt = Eigen::Vector2d::Zero(), rt = Eigen::Vector2d::Zero();
      for (int c = 1; c < d; ++c) xt[c - 1] = px[l + c], rt[c - 1] = pr[l + c];
      const double ct = d == 2 ? pd[l + 1] : std::max(pd[l + 1], pd[l + 2]);
      bool roller = false;
      for (int c = 1; c < d; ++c) roller = roller || roller_fixed(md, kk, c);
      if (roller) {
        for (int c = 1; c < d; ++c)
          if (roller_fixed(md, kk, c)) fixed.push_back(iv + c), pf[l + c] = -px[l + c];
      } else if (w * lam > 0) {
        const Eigen::Vector2d y = -rt + ct * xt;
        const double ny = y.norm();
        if (ny <= w * lam || hold_stick[q]) {
          st |= 2;
          for (int c = 1; c < d; ++c) fixed.push_back(iv + c), pf[l + c] = -px[l + c];
        } else {
          const Eigen::Vector2d t = y / ny;
          slip_dir[q] = t;
          // ρ: the slip now, or the slip this step will reach ((|y| − wλ)/c_t) where that is
          // larger (a node that just left stick has x_τ = 0). A smaller ρ (stiffer) than the true
          // curvature would let x_τ overshoot through 0 and the direction t flip every step.
          const double rho = std::max(xt.norm(), (ny - w * lam) / ct);
          for (int c = 1; c < d; ++c) pr[l + c] += w * lam * t[c - 1];
          if (d == 2) {
            // One tangent direction: I − t tᵀ = 0, the slip force is constant on the branch.
          } else {
            const Eigen::Matrix2d Jt = w * lam / rho * (Eigen::Matrix2d::Identity() - t * t.transpose());
            B[4] = Jt(0, 0), B[5] = Jt(0, 1), B[7] = Jt(1, 0), B[8] = Jt(1, 1);
          }
          if (d == 2) st |= (t[0] >= 0 ? 8 : 16);  // a reversal of the slip direction is a change
        }
      }
      if (md.normal_law && !contact) {
        // The branch of p: the index of the breakpoint interval x_ν lies in (eq. (32)'s pieces).
        const auto& r = md.normal_law->breakpoints();
        st |= 32 * static_cast<int>(1 + (std::upper_bound(r.begin(), r.end(), xn) - r.begin()));
      }
      status[q] = st;
      if (st != prev_status[q]) ++changed;
      PetscInt idx[3] = {iv, iv + 1, iv + 2};
      HC_PETSC(MatSetValues(J, d, idx, d, idx, B, ADD_VALUES));
    }
    HC_PETSC(VecRestoreArrayRead(x.v, &px));
    HC_PETSC(VecRestoreArrayRead(diagK.v, &pd));
    HC_PETSC(VecRestoreArray(R.v, &pr));
    HC_PETSC(VecRestoreArray(fixv.v, &pf));
    HC_PETSC(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    HC_PETSC(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
    long changed_all = 0;
    MPI_Allreduce(&changed, &changed_all, 1, MPI_LONG, MPI_SUM, comm);
    prev_status = status;
    unchanged = changed_all == 0 ? unchanged + 1 : 0;
    // rhs = −R on free rows; the fixed rows carry their prescribed step (fixv), and the columns
    // MatZeroRowsColumns removes move their contribution to the right-hand side.
    HC_PETSC(VecCopy(R.v, rhs.v));
    HC_PETSC(VecScale(rhs.v, -1.0));
    HC_PETSC(MatZeroRowsColumns(J, static_cast<PetscInt>(fixed.size()), fixed.data(), diag_scale, fixv.v, rhs.v));
    PetscReal res;
    HC_PETSC(VecNorm(rhs.v, NORM_INFINITY, &res));
    // Converged at this iterate: the statuses it gives are those of the last step, and the residual
    // of the semismooth system (equilibrium on the free rows, the fixed unknowns' misfit times the
    // diagonal) is at most ssn_tol of the load scale. No step is taken: at 10⁷ unknowns the steps
    // that only confirmed round-off cost 50 s each.
    if (k > 1 && changed_all == 0 && res / F_s <= opt.petsc.ssn_tol) {
      converged = true;
      log_info() << "ssn " << k << ": statuses held, residual " << short_number(res / F_s)
                 << " <= solver.petsc.ssn_tol: converged";
      --k;  // the steps taken
      break;
    }
    // Inexact Newton: a step that may still change statuses needs only ssn_rtol; once they hold,
    // ssn_rtol² per step (the λ coupling contracts by about that much anyway), never below ksp_rtol.
    const double rtol = std::max(opt.petsc.ksp_rtol, changed_all > 0 ? opt.petsc.ssn_rtol
                                                                     : opt.petsc.ssn_rtol * opt.petsc.ssn_rtol);
    PC pc;
    HC_PETSC(KSPGetPC(ksp.k, &pc));
    HC_PETSC(KSPSetOperators(ksp.k, J, J));
    HC_PETSC(PCSetReusePreconditioner(pc, rebuild ? PETSC_FALSE : PETSC_TRUE));
    HC_PETSC(KSPSetTolerances(ksp.k, rtol, PETSC_DEFAULT, PETSC_DEFAULT, opt.petsc.ksp_max_it));
    const auto t_ksp = clk::now();
    HC_PETSC(VecSet(dx.v, 0.0));
    HC_PETSC(KSPSolve(ksp.k, rhs.v, dx.v));
    PetscInt its;
    HC_PETSC(KSPGetIterationNumber(ksp.k, &its));
    krylov_total += its;
    ++newton_total;
    // The hierarchy's quality: CG iterations per decade of residual reduction. Rebuilt when a
    // step with the reused hierarchy needs pc_rebuild times the reference (built_per_decade).
    PetscReal rnorm;
    HC_PETSC(KSPGetResidualNorm(ksp.k, &rnorm));
    PetscReal bnorm;
    HC_PETSC(VecNorm(rhs.v, NORM_2, &bnorm));
    const double decades = (rnorm > 0 && bnorm > 0) ? std::max(0.5, std::log10(bnorm / rnorm)) : 1.0;
    const double per_decade = static_cast<double>(its) / decades;
    const bool built = rebuild;
    if (rebuild) {
      built_per_decade = per_decade, rebuild = false, reference_pending = true;
    } else if (reference_pending) {
      built_per_decade = std::max(built_per_decade, per_decade), reference_pending = false;
    } else if (per_decade > opt.petsc.pc_rebuild * std::max(built_per_decade, 1.0)) {
      rebuild = true;
    }
    ksp_check(ksp.k, "ssn Newton step " + std::to_string(k));  // exit 3 naming PETSc's reason
    HC_PETSC(VecAXPY(x.v, 1.0, dx.v));
    // A sliding node whose step carried x_τ through 0 (x_τ · t < 0: the friction force it was
    // given is more than equilibrium needs, so it should stick) is put at x_τ = 0 and held at stick
    // for the next step; the step after that reads stick or slip from the relaxed neighbours.
    // Without this, nodes at the stick limit chattered (slip, reversal, slip...) and the iteration
    // stalled at a residual ~1e-4 (3D scene, n = 48 and 70).
    long projected = 0;
    {
      PetscScalar* pxx;
      HC_PETSC(VecGetArray(x.v, &pxx));
      for (size_t q = 0; q < my_nodes.size(); ++q) {
        hold_stick[q] = 0;  // one step only
        if (slip_dir[q].squaredNorm() == 0) continue;
        const PetscInt l = cdof(my_nodes[q]) - lo;
        double dot = 0;
        for (int c = 1; c < d; ++c) dot += pxx[l + c] * slip_dir[q][c - 1];
        hold_stick[q] = dot < 0;
        if (dot < 0) {
          for (int c = 1; c < d; ++c) pxx[l + c] = 0;
          ++projected;
        }
      }
      HC_PETSC(VecRestoreArray(x.v, &pxx));
      long all = 0;
      MPI_Allreduce(&projected, &all, 1, MPI_LONG, MPI_SUM, comm);
      projected = all;
    }
    PetscReal step, scale;
    HC_PETSC(VecNorm(dx.v, NORM_INFINITY, &step));
    HC_PETSC(VecNorm(x.v, NORM_INFINITY, &scale));
    const double rel = scale > 0 ? step / scale : 0.0;
    steps.push_back({{"step", k}, {"status_changes", changed_all}, {"slip_reversals", projected}, {"krylov", its}, {"rtol", rtol},
                     {"pc_built", built}, {"residual", res / F_s}, {"dx_rel", rel}, {"seconds", since(t_ksp)}});
    log_info() << "ssn " << k << ": " << changed_all << " status changes, residual " << short_number(res / F_s)
               << ", CG " << its << " it (rtol " << short_number(rtol) << (built ? ", AMG built" : "")
               << "), |dx|/|x| " << short_number(rel)
               << (projected > 0 ? ", " + std::to_string(projected) + " slip reversals set to 0" : "")
               << ", memory " << short_number(double(current_rss_kb()) / 1024.0) << " MB (rank 0)";
    // Done when the statuses have held for two steps and the step reached round-off or stopped
    // decreasing there (the λ coupling contracts linearly; round-off ends it).
    if (unchanged >= 2 && (rel <= 1e-14 || (rel <= 1e-10 && step >= prev_step))) {
      converged = true;
      break;
    }
    prev_step = unchanged >= 1 ? step : INF;
  }
  restore_band(band);  // K as assembled, for the certificate (md.Kx_apply) and the energies
  timings["backend"] = since(t_loop);
  U_s = 1;
  sol.x_scale = 1;
  sol.f_scale = F_s;
  OuterIteration rec;
  rec.backend.iterations = static_cast<int>(std::min(k, opt.petsc.ssn_max_iters));
  rec.backend.seconds = timings["backend"];
  rec.backend.message = converged ? "ssn converged in " + std::to_string(k) + " Newton steps, " +
                                        std::to_string(krylov_total) + " CG iterations"
                                  : "ssn: no convergence in " + std::to_string(opt.petsc.ssn_max_iters) +
                                        " Newton steps (solver.petsc.ssn_max_iters; the statuses still changed or "
                                        "the step did not reach round-off)";
  rec.backend.status = converged ? SolveStatus::CONVERGED : SolveStatus::MAX_ITERATIONS;
  sol.history.push_back(rec);
  sol.backend_ok = converged;
  if (!converged) sol.message = rec.backend.message;
  stages = steps;
  Eigen::VectorXd xg = gather(x.v);
  finish(sol, std::move(xg), t0);
  timings.erase("backend");
  return std::move(sol);
}

Solution Engine::run() {
  const auto t0 = clk::now();
#if defined(PETSC_HAVE_HYPRE)
  // GAMG's Galerkin products P^T A P on more than one rank: PETSc's own MPIAIJ algorithms keep
  // A P's local rows (and P^T's) for reuse, 1.2-1.9 KB per unknown at the fine level; hypre's
  // product keeps none (3D scene, 2 ranks, 48^3: 3.7 -> 2.3 KB per unknown with the rigid modes,
  // 2.4 -> 1.8 with the translations, the same CG iterations). On one rank PETSc's sequential
  // product is already lean (and hypre's made the hierarchy indefinite there). -matptap_via set
  // by the user (solver.petsc.options, PETSC_OPTIONS) wins.
  if (size > 1) option_default("-matptap_via", "hypre");
#endif
  distribute();
  assemble();
  near_null_space();
  if (tao_type(opt.backend) == "ssn") return run_ssn(t0);
  elastic_solve();
  sol.backend = "tao:" + tao_type(opt.backend) + " (PETSc, " + std::to_string(size) + " rank" +
                (size > 1 ? "s" : "") + ")";
  sol.formulation = "full";
  sol.x_scale = U_s;
  sol.f_scale = F_s * U_s;
  sol.fixed_point_converged = true;
  if (opt.smallness)
    sol.skipped.push_back("smallness: (21) is evaluated by the cholmod engine only (it needs a factorization)");
  if (!md.normal_law) sol.skipped.push_back("normal_compliance: no soft layer (contact.normal_law.type = none)");
  if (!md.friction) sol.skipped.push_back("friction: frictionless (contact.friction.type = none)");
  if (md.friction && !md.friction->depends_on_u_nu()) sol.skipped.push_back("fixed_point: F_b does not depend on u_nu");
  if (md.gap.is_infinite()) sol.skipped.push_back("bounds: no rigid obstacle (g = inf)");

  // Nothing nonlinear and no obstacle: the elastic solve is the answer.
  if (!md.normal_law && !md.friction && md.gap.is_infinite() && md.contact.fixed_local.empty()) {
    sol.backend = "none (PETSc CG linear solve)";
    sol.skipped.push_back("backend: linear elasticity, solved by one CG solve");
    finish(sol, gather(zfree.v), t0);
    return std::move(sol);
  }
  // Continuation schedule: driver/solve.cpp's, ε_s = max(ε_final, ε_start·factor^s).
  if (md.normal_law || md.friction) {
    const auto at_final = [](double e, double fin) { return e <= fin * (1 + 1e-9); };
    for (double e = opt.eps_start;; e *= opt.eps_factor) {
      const double et = at_final(e, opt.eps_tau) ? opt.eps_tau : e;
      const double en = at_final(e, opt.eps_nu) ? opt.eps_nu : e;
      schedule.emplace_back(et, en);
      if (et == opt.eps_tau && en == opt.eps_nu) break;
    }
  } else {
    schedule.emplace_back(opt.eps_tau, opt.eps_nu);  // only the bounds: no width is used
    sol.skipped.push_back("continuation: nothing is smoothed");
  }
  // Start from zero (inside the bounds: g ≥ 0), λ frozen there.
  HC_PETSC(VecSet(zs.v, 0.0));
  if (md.friction)
    for (size_t q = 0; q < my_nodes.size(); ++q) lambda[q] = md.friction->F(0.0);
  prev_c = local_gamma3(zs.v);
  for (size_t stage = 0; stage < schedule.size(); ++stage) {
    if (!run_stage(stage)) break;
    // driver/solve.cpp's early stop: once a stage barely moved the answer, polish a copy; if the
    // certificate passes, the remaining stages are not needed.
    if (stage + 1 < schedule.size() && settled()) {
      Eigen::VectorXd x = U_s * gather(zs.v);
      const PolishResult pr = polish_with_readings(x, stage);
      if (pr.accepted) {
        Solution trial = sol;
        trial.polish = pr;
        finish(trial, x, t0);
        if (trial.certificate.passed) {
          trial.skipped.push_back("continuation: stages " + std::to_string(stage + 1) + ".." +
                                  std::to_string(schedule.size() - 1) + " not run: the polished answer after stage " +
                                  std::to_string(stage) + " was certified (solver.continuation.certify_below)");
          log_info() << "continuation: certified after stage " << stage;
          return trial;
        }
      }
    }
  }
  Eigen::VectorXd x = U_s * gather(zs.v);
  if (opt.polish && sol.fixed_point_converged) {
    sol.polish = polish_with_readings(x, schedule.size() - 1);
    log_info() << "polish: " << (sol.polish.accepted ? "accepted" : "rejected") << ", certificate "
               << sol.polish.before << " -> " << sol.polish.after << " in " << sol.polish.iterations
               << " Newton iterations" << (sol.polish.note.empty() ? "" : " (" + sol.polish.note + ")");
  } else if (!opt.polish) {
    sol.skipped.push_back("polish: solver.polish = false");
  }
  finish(sol, std::move(x), t0);
  return std::move(sol);
}

}  // namespace

Solution solve(Model& md, const SolveOptions& opt, MPI_Comm comm, EngineReport& report) {
  Engine e(md, opt, comm, report);
  return e.run();
}

}  // namespace hemicontact::petsc_engine
