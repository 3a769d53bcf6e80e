#pragma once
/// @file engine_impl.hpp  The petsc engine's inside, shared by its source files (src/petsc/):
///   petsc_handles.cpp       PETSc's error handler, HC_PETSC's failure, memory readings, tao_type
///   petsc_solvers.cpp       option defaults, the preconditioners (GAMG made anew for TAO), CG set-up
///   petsc_assembly.cpp      K, f, the bounds, the near-null space, the elastic solve, K's saved band
///   petsc_tao.cpp           the smoothed energy and its Hessian (energy/'s nodal kernels), TAO's
///                           minimizations, λ's relaxation, a stage's smoothing
///   petsc_ssn.cpp           backend ssn (semismooth Newton on the unsmoothed statuses)
///   petsc_polish.cpp        the exact polish with fixed statuses
///   petsc_engine.cpp        the run's set-up, then solver/outer_loop's algorithm over the engine's
///                           steps (its polished copy, its finish), the report, solve()
///   petsc_slab_distribution.cpp  the slabs (make_slab), PETSc's numbering of the pieces, the ghost rows
///   petsc_block_distribution.cpp the blocks of cell columns (make_block)
///   petsc_plex_distribution.cpp  Gmsh (and other) meshes distributed by DMPlex (make_plex_piece)
///   petsc_slab_finish.cpp   the certificate, energies and status counts by reductions, the piece
///   petsc_slab_output.cpp   the files: a piece per rank, the .pvtu, report.json (not the engine's)
/// Not installed and not part of the library: only hemicontact-mpi's sources include it.

#include "petsc_engine.hpp"

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/check/status_equations.hpp>
#include <hemicontact/energy/contact_energy.hpp>
#include <hemicontact/solver/outer_loop.hpp>

#include <petscksp.h>
#include <petscmat.h>
#include <petsctao.h>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hemicontact::petsc_engine {

// The request half of every exchange between a piece's ghosts and their owners (the ghost rows,
// the Γ3 weights): the ghosts grouped by owner, and what each owner was asked.
struct GhostAsk {
  std::vector<int> scount, sdispl;  // ghosts asked of each rank, and where each group starts
  std::vector<int> rcount, rdispl;  // numbers each rank asked of this one
  std::vector<Index> ghost;         // the local ghost node of request i (grouped by owner)
  std::vector<Index> answer;        // the local owned node that answers asked number i
};
// Collective: the ghosts' global numbers to their owners, and each owner's node of each.
GhostAsk ask_owners(const Piece& pc, MPI_Comm comm);
std::vector<Index> owned_nodes_of(const Piece& pc, const std::vector<long>& asked);
// Per mesh node: its Γ3 index k, or −1.
std::vector<Index> gamma3_index_of_nodes(const Model& md);
// The answers (@p m values per asked node, in ask.answer's order) back to the ghosts: @return m
// values per ghost, in ask.ghost's order. Collective.
template <class T>
std::vector<T> answer_ghosts(const GhostAsk& a, const std::vector<T>& answers, int m, MPI_Datatype type, MPI_Comm comm) {
  const size_t S = a.scount.size();
  std::vector<int> sc(S), sd(S), rc(S), rd(S);
  for (size_t q = 0; q < S; ++q)
    sc[q] = a.rcount[q] * m, sd[q] = a.rdispl[q] * m, rc[q] = a.scount[q] * m, rd[q] = a.sdispl[q] * m;
  std::vector<T> got(a.ghost.size() * static_cast<size_t>(m));
  MPI_Alltoallv(answers.data(), sc.data(), sd.data(), type, got.data(), rc.data(), rd.data(), type, comm);
  return got;
}

}  // namespace hemicontact::petsc_engine

// PETSc's Vec and Mat are global typedefs; inside namespace hemicontact the names are Eigen's, so
// PETSc objects are written ::Vec and ::Mat throughout.

namespace hemicontact::petsc_engine::detail {

// A PETSc call that fails is a bug or a resource problem (EXIT_INTERNAL), or, with options of the
// user's set (solver.petsc.options), most likely one of them: EXIT_INPUT naming them.
[[noreturn]] void petsc_failure(PetscErrorCode ierr, const char* call);
#define HC_PETSC(call)                                                                         \
  do {                                                                                         \
    const PetscErrorCode hc_ierr_ = (call);                                                    \
    if (hc_ierr_) ::hemicontact::petsc_engine::detail::petsc_failure(hc_ierr_, #call);         \
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

// A number in a log line or a message: 3 significant digits.
inline std::string short_number(double x) { return fmt(x, 3); }

double allreduce_max(double x, MPI_Comm comm);
double allreduce_sum(double x, MPI_Comm comm);
/// @return this process's peak resident memory (kB).
long peak_rss_kb();

// A PETSc option's default: set only where the user set nothing (solver.petsc.options,
// PETSC_OPTIONS), so that theirs still wins.
void option_default(const std::string& name, const char* value);
// BoomerAMG's defaults for elasticity in 3D, where the KSP's preconditioner is hypre's.
void hypre_defaults(KSP ksp);
// GAMG's defaults (its own eigenvalue estimate for the smoothers), where the KSP's is GAMG.
void gamg_defaults(KSP ksp);
// TAO's Newton KSP with GAMG: a shell that makes a fresh GAMG at every set-up.
void fresh_gamg(KSP ksp);

// The distributed problem: K, f and the bounds in PETSc, the Γ3 nodes this rank owns, the smoothing
// and frozen friction bounds, and the counters for the report. With a TAO backend it supplies the
// steps of the outer algorithm (solver/outer_loop.hpp), which decides between them as it does for
// the CHOLMOD engine; backend ssn is its own Newton on the unsmoothed statuses.
class Engine : private OuterStepper {
 public:
  // md is this rank's piece; the answer's vectors stay on the ranks (out).
  Engine(const Model& md, const Piece& slab, const SolveOptions& opt, MPI_Comm comm, EngineReport& rep, SlabResult& out,
         const Vec* start);
  ~Engine() {
    if (rigid) MatNullSpaceDestroy(&rigid);
  }
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;
  Solution run();

 private:
  // ---- backend ssn (petsc_ssn.cpp)
  struct Ssn;        // the iterate, work vectors and what one step passes to the next
  struct SsnArrays;  // the local arrays one linearization reads and writes
  Solution run_ssn(clk::time_point t0);
  void ssn_describe();
  void ssn_setup(Ssn& s);
  void ssn_start(Ssn& s);
  long ssn_linearize(Ssn& s, int k);
  int ssn_node(Ssn& s, size_t q, int k, const SsnArrays& a, double* B, double slope_probe);
  void ssn_couple(Ssn& s, ::Mat J);
  double ssn_merit(Ssn& s, ::Vec xt);
  double ssn_step_length_at(Ssn& s);
  double ssn_right_hand_side(Ssn& s);
  bool ssn_step(Ssn& s, int k, long changed_all, double res);
  bool ssn_judge_hierarchy(Ssn& s, PetscInt its);
  long ssn_stop_reversals(Ssn& s, ::Vec xt, bool hold);
  Solution ssn_finish(Ssn& s, int k, bool converged, clk::time_point t0, clk::time_point t_loop);
  // The rows of K that ssn's J changes (those with a column on a Γ3 unknown), saved so that K can
  // be changed in place and put back exactly.
  struct BandRows {
    std::vector<PetscInt> rows, start, cols;  // row r's entries: cols[start[r] .. start[r + 1])
    std::vector<PetscScalar> vals;
  };
  BandRows save_band() const;
  void restore_band(const BandRows& b) const;
  // ---- the pieces' numbering and judge (petsc_slab_distribution.cpp, petsc_slab_finish.cpp)
  void distribute_slabs();
  void exchange_ghosts(const std::vector<Index>& sel);
  void check_same_place(Index v, const double* there) const;  // a ghost is where its owner has it
  void finish_slabs(Solution& s, ::Vec x, clk::time_point t0);
  // A piece's evaluation at x (R = K x − f): its u, Γ3 state (slab_piece), then the judge over the
  // ranks: certificate, statuses read at o.status_tol, Γ3 energies, counts (slab_judge), into p; slab_evaluate
  // makes both for a candidate x (the polish's) without touching the run's piece (slab_out).
  void slab_piece(::Vec x, ::Vec R, Solution& p);
  void slab_judge(Solution& p, const SolveOptions& o) const;
  Solution slab_evaluate(::Vec x, const SolveOptions& o);
  void slab_energies(Solution& s, ::Vec x, ::Vec R) const;
  void slab_report(Solution& s);
  void record();  // the engine's record for report.json ("petsc"): counts, memory, partition
  void close_record(Solution& s, clk::time_point t0, clk::time_point t1);
  void init();  // rank, size, d, lagged; refuses a nonlinear material
  // ---- set-up
  void assemble();
  void tao_vectors();  // the bounds and TAO's work vectors (not made for ssn)
  void near_null_space();
  void elastic_solve();
  // ---- the smoothed energy in scaled unknowns (callbacks of TAO)
  double energy(::Vec zs, ::Vec g);  // value, and the gradient into g (scaled)
  void hessian(::Vec zs, ::Mat H);   // K + nodal blocks, scaled; normal term clamped ≥ 0
  std::shared_ptr<const NodalLayout> owned_layout() const;
  Vec owned_lambda() const;
  static PetscErrorCode tao_objgrad(Tao, ::Vec x, PetscReal* f, ::Vec g, void* ctx);
  static PetscErrorCode tao_hessian(Tao, ::Vec x, ::Mat H, ::Mat Hpre, void* ctx);
  // ---- the steps of the outer algorithm (OuterStepper; petsc_tao.cpp, petsc_engine.cpp)
  Solution& solution() override { return sol; }
  size_t stage_count() const override { return schedule.size(); }
  bool lagged() const override { return is_lagged; }
  std::string backend_name() const override { return "tao:" + tao_type(opt.backend); }
  void set_smoothing(size_t stage) override;
  OuterIteration minimize(size_t stage) override;
  LambdaChange relax_lambda() override;
  // The polish (petsc_polish.cpp) reads and writes a PETSc vector (owned rows) and the statuses of
  // the owned Γ3 nodes.
  bool polish_exists() const override { return true; }
  std::optional<Solution> certified_copy() override;
  Solution finish() override;
  PolishResult polish(::Vec x_io, const SolveOptions& read_opt, const Solution& s0);
  NodeRows polish_rows(Index k, const PetscScalar* px, const Solution& s0, double delta) const;
  std::vector<PetscInt> polish_start(::Vec x, const Solution& s0, double delta) const;
  bool polish_linearize(::Vec x, ::Vec R, ::Mat J, const Solution& s0, double delta,
                        const std::vector<PetscInt>& fixed);
  void polish_accept(::Vec x, const Solution& s0, double delta, PolishResult& r, ::Vec x_io);
  std::string piece_rejection(const Solution& s0, const Solution& s1, double delta, double before) const;
  PolishResult polish_with_readings(::Vec x, size_t stage);
  // U_s zs, the current iterate in the model's units, in a new vector.
  void unscaled_iterate(PVec& x) const;
  // ---- helpers
  Eigen::VectorXd local_gamma3(::Vec zs) const;
  double first_order_residual(::Vec zs, ::Vec g, ::Vec lo_s, ::Vec up_s) const;
  void scaled_bound(::Vec b, ::Vec out) const;  // b / U_s, ±PETSC_INFINITY kept (no overflow)
  void ksp_check(KSP ksp, const std::string& what) const;
  void set_pc(KSP ksp, const std::string& type) const;
  void create_cg(PKsp& ksp, const char* prefix, KSPNormType norm = KSP_NORM_DEFAULT) const;

  const Model& md;
  SolveOptions opt;
  MPI_Comm comm;
  EngineReport& rep;
  int rank = 0, size = 1, d = 2, bs = 1;
  PetscInt n = 0, lo = 0, hi = 0;  // global size, owned rows [lo, hi) (PETSc's numbering)
  // PETSc's numbering of the piece's unknowns (distribute_slabs): the owned ones, in the piece's
  // x order (DofMap: interior node-major, then Γ3), are the rows [lo, hi); a ghost's are its owner's.
  std::vector<PetscInt> perm;  // x index → PETSc index (−1: an outer ghost's, without a row)
  std::vector<Index> mine;     // x index of owned row lo + l
  PetscInt P(Index x) const { return perm[static_cast<size_t>(x)]; }
  Index X(PetscInt l) const { return mine[static_cast<size_t>(l)]; }
  // Γ3 node k's ν row in PETSc's numbering; its τ rows follow it.
  PetscInt cdof(Index k) const { return P(md.dofs.contact_dof(k, 0)); }
  std::vector<Index> my_nodes;     // Γ3 nodes whose rows this rank owns
  PMat K;
  PVec f, lower, upper, zs, zfree, work, grad;
  MatNullSpace rigid = nullptr;
  double U_s = 1, F_s = 1;
  std::vector<std::pair<double, double>> schedule;
  double eps_tau = 0, eps_nu = 0;                // absolute widths of the current stage
  // energy/'s nodal terms on the owned Γ3 nodes (owned_layout): j_ε of the current stage's
  // mollified p_ν, and friction with the current ε_τ and frozen λ (lambda, copied at each change).
  std::shared_ptr<const NodalLayout> nodal;
  std::unique_ptr<NormalComplianceEnergy> normal_term;
  std::unique_ptr<FrictionEnergy> friction_term;
  std::vector<double> lambda;                    // frozen F_b per owned Γ3 node (my_nodes order)
  Eigen::VectorXd prev_c;                        // owned Γ3 unknowns after the previous minimization
  bool is_lagged = false;  // λ = F_b(u_ν) depends on the answer: the outer fixed point runs
  Solution sol;  // the answer being built (history, verdicts)
  int k_total = 0;
  clk::time_point t_run;  // the run's start (run())
  long newton_total = 0, krylov_total = 0, polish_krylov = 0, polish_newton = 0;
  nlohmann::json stages = nlohmann::json::array();
  std::map<std::string, double> timings;
  const Piece& slab;     // md is this rank's piece
  SlabResult& slab_out;  // and its piece of the answer goes here
  const Vec* start;      // ssn's start: the piece's reduced unknowns (null: zero)
};

}  // namespace hemicontact::petsc_engine::detail
