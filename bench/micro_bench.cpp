// hemicontact_micro_bench — Google Benchmark micro-benchmarks of the pieces a solve is made of.
//
// What is measured (scene: problems/sofonea2017-fig2.json at mesh.n = n, symmetric mesh):
//   Assembly/n              K = Σ_T |T| Bᵀ D B (assemble_stiffness), n = 64, 256
//   EnergyValueGrad/F/n     Π_λ value + gradient as solve() builds it, F = full (sparse, all free
//                           dofs) or condensed (dense Schur on the Γ3 unknowns), n = 64, 256
//   EnergyHessian/F/n       the same energy's Hessian on its fixed pattern (true Hessian, Psd::NONE)
//   LinearFactorSolve/n     the linear elastic problem: SparseCholesky analyze + factorize + solve
//   Condensation/n          Condensation(Kx, fx, Γ3): analyze + factorize + Schur from the trailing
//                           block + y = K⁻¹f — what the condensed formulation pays once per solve
//                           (n = 128, 256, 512 for both)
// Sample runs:
//   build-bench/bench/hemicontact_micro_bench
//   build-bench/bench/hemicontact_micro_bench --benchmark_filter='Condensation|LinearFactor'
//   build-bench/bench/hemicontact_micro_bench --benchmark_format=json --benchmark_out=micro.json
// Sized for the 2-core machine: the whole run takes well under 2 minutes (most of it building the
// n = 512 model twice is avoided by grouping the benchmarks by mesh size, see main()).

#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/contact/mollified_law.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/energy/contact_energy.hpp>
#include <hemicontact/energy/elastic_energy.hpp>
#include <hemicontact/energy/total_energy.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/fem/condensation.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>

#include <benchmark/benchmark.h>

#include <memory>
#include <string>

using namespace hemicontact;

namespace {

const std::string SCENE = std::string(HEMICONTACT_SOURCE_DIR) + "/problems/sofonea2017-fig2.json";

// One model at a time: the benchmarks are registered grouped by n, so each size is built once and
// the n = 512 model (≈ 0.5 M dofs) does not stay in memory next to the others.
const Model& model_at(int n) {
  static int cached_n = -1;
  static std::unique_ptr<Model> cached;
  if (n != cached_n) {
    cached.reset();
    const auto scene = load_scene(SCENE, {"mesh.n=" + std::to_string(n)});
    cached = std::make_unique<Model>(build_model(scene, scene_directory(SCENE)));
    cached_n = n;
  }
  return *cached;
}

// Π_λ exactly as solve() assembles it (src/solver/solve.cpp, make_formulation), smoothed at
// ε = 1e-6 U_s, evaluated at a realistic point: the unconstrained elastic solution clipped at the
// obstacle (so the normal law sees every branch along Γ3), with λ_i = F_b(x_ν,i) frozen there.
struct EnergySetup {
  std::unique_ptr<TotalEnergy> energy;
  std::shared_ptr<const Condensation> cond;
  Vec x;
};

std::unique_ptr<EnergySetup> make_energy(const Model& md, bool condensed) {
  auto e = std::make_unique<EnergySetup>();
  const Index nc = md.contact.size();
  const int d = md.dim();
  NodalDofs nd;
  nd.dim = d;
  nd.w = md.contact.w;
  Vec z_free;
  if (condensed) {
    e->cond = std::make_shared<const Condensation>(md.Kx.lower(), md.fx, d * nc);
    e->energy = std::make_unique<TotalEnergy>(d * nc, dense_lower_pattern(d * nc));
    e->energy->add(std::make_shared<CondensedElasticEnergy>(std::shared_ptr<const Mat>(e->cond, &e->cond->S()),
                                                            e->cond->y_C(), e->cond->constant()));
    for (Index k = 0; k < nc; ++k) nd.first.push_back(d * k);
    z_free = e->cond->y_C();
  } else {
    SparseCholesky chol;
    chol.compute(md.Kx.lower());
    z_free = chol.solve(md.fx);
    auto elastic = std::make_shared<ElasticEnergy>(md.Kx);
    e->energy = std::make_unique<TotalEnergy>(md.dofs.n_free(), elastic->lower());
    e->energy->add(elastic);
    e->energy->add(std::make_shared<LoadEnergy>(md.fx));
    for (Index k = 0; k < nc; ++k) nd.first.push_back(md.dofs.contact_dof(k, 0));
  }
  const double U = z_free.cwiseAbs().maxCoeff();
  e->x = z_free;
  Vec lambda(nc);
  for (Index k = 0; k < nc; ++k) {
    double& xn = e->x[nd.first[k]];
    xn = std::min(xn, md.contact.g[k]);
    lambda[k] = md.friction ? md.friction->F(xn) : 0.0;
  }
  const auto layout = std::make_shared<const NodalLayout>(nd, e->energy->hessian_pattern());
  if (md.normal_law)
    e->energy->add(std::make_shared<NormalComplianceEnergy>(
        layout, std::make_shared<const MollifiedLaw>(md.normal_law, 1e-6 * U)));
  if (md.friction) e->energy->add(std::make_shared<FrictionEnergy>(layout, 1e-6 * U, lambda));
  return e;
}

void set_size_counters(benchmark::State& state, const Model& md) {
  state.counters["dofs"] = static_cast<double>(md.dofs.n_free());
  state.counters["gamma3"] = static_cast<double>(md.contact.size());
}

void BM_Assembly(benchmark::State& state, int n) {
  const Model& md = model_at(n);
  for (auto _ : state) {
    SpMat K = assemble_stiffness(md.mesh, *md.material);
    benchmark::DoNotOptimize(K.valuePtr());
  }
  set_size_counters(state, md);
}

void BM_EnergyValueGrad(benchmark::State& state, int n, bool condensed) {
  const Model& md = model_at(n);
  const auto e = make_energy(md, condensed);
  Vec g(e->energy->size());
  for (auto _ : state) {
    double v = e->energy->value(e->x);
    e->energy->gradient(e->x, g);
    benchmark::DoNotOptimize(v);
    benchmark::DoNotOptimize(g.data());
  }
  set_size_counters(state, md);
  state.counters["unknowns"] = static_cast<double>(e->energy->size());
}

void BM_EnergyHessian(benchmark::State& state, int n, bool condensed) {
  const Model& md = model_at(n);
  const auto e = make_energy(md, condensed);
  SpMat H = e->energy->hessian_pattern();
  for (auto _ : state) {
    e->energy->hessian(e->x, H, Psd::NONE);
    benchmark::DoNotOptimize(H.valuePtr());
  }
  set_size_counters(state, md);
  state.counters["unknowns"] = static_cast<double>(e->energy->size());
  state.counters["hess_nnz"] = static_cast<double>(H.nonZeros());
}

void BM_LinearFactorSolve(benchmark::State& state, int n) {
  const Model& md = model_at(n);
  double analyze = 0, factor = 0;
  for (auto _ : state) {
    SparseCholesky chol;
    chol.compute(md.Kx.lower());
    Vec u = chol.solve(md.fx);
    benchmark::DoNotOptimize(u.data());
    analyze += chol.analyze_seconds();
    factor += chol.factorize_seconds();
  }
  set_size_counters(state, md);
  state.counters["analyze_s"] = benchmark::Counter(analyze, benchmark::Counter::kAvgIterations);
  state.counters["factor_s"] = benchmark::Counter(factor, benchmark::Counter::kAvgIterations);
}

void BM_Condensation(benchmark::State& state, int n) {
  const Model& md = model_at(n);
  const Index m = md.dim() * md.contact.size();
  double analyze = 0, factor = 0, schur = 0;
  for (auto _ : state) {
    Condensation cond(md.Kx.lower(), md.fx, m);
    benchmark::DoNotOptimize(cond.S().data());
    analyze += cond.analyze_seconds();
    factor += cond.factorize_seconds();
    schur += cond.schur_seconds();
  }
  set_size_counters(state, md);
  state.counters["analyze_s"] = benchmark::Counter(analyze, benchmark::Counter::kAvgIterations);
  state.counters["factor_s"] = benchmark::Counter(factor, benchmark::Counter::kAvgIterations);
  state.counters["schur_s"] = benchmark::Counter(schur, benchmark::Counter::kAvgIterations);
}

// Iteration counts: fixed for the factorizations (one at n = 512 takes seconds, and Google
// Benchmark's default 0.5 s minimum would run it once, with no spread), a short minimum time for
// the cheap cases. iters = 0: by minimum time.
benchmark::internal::Benchmark* timed(benchmark::internal::Benchmark* b, int iters) {
  b->Unit(benchmark::kMillisecond)->UseRealTime();
  return iters > 0 ? b->Iterations(iters) : b->MinTime(0.3);
}

void register_all() {
  using benchmark::RegisterBenchmark;
  for (const int n : {64, 128, 256, 512}) {
    const std::string N = "/" + std::to_string(n);
    if (n == 64 || n == 256) {
      timed(RegisterBenchmark(("Assembly" + N).c_str(), BM_Assembly, n), n == 256 ? 10 : 0);
      for (const bool c : {false, true}) {
        const std::string F = c ? "/condensed" : "/full";
        timed(RegisterBenchmark(("EnergyValueGrad" + F + N).c_str(), BM_EnergyValueGrad, n, c), 0);
        timed(RegisterBenchmark(("EnergyHessian" + F + N).c_str(), BM_EnergyHessian, n, c), 0);
      }
    }
    if (n >= 128) {
      const int iters = n == 512 ? 3 : n == 256 ? 5 : 0;
      timed(RegisterBenchmark(("LinearFactorSolve" + N).c_str(), BM_LinearFactorSolve, n), iters);
      timed(RegisterBenchmark(("Condensation" + N).c_str(), BM_Condensation, n), iters);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  set_log_level(LogLevel::WARN);  // build_model's progress lines would interleave with the table
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
