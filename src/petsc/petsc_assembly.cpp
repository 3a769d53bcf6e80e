#include "engine_impl.hpp"

#include <hemicontact/core/log.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/problem/node_rules.hpp>

#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hemicontact::petsc_engine::detail {

// Each rank assembles its rows of the reduced stiffness Kx (symmetric, so row i is column i of the
// column-major matrix) into PETSc with exact preallocation, and its part of f and of the bounds.
void Engine::assemble() {
  const auto t0 = clk::now();
  // The piece's model keeps no K_x (build_model(..., stiffness = false)): this rank assembles its
  // own columns, i.e. rows, and frees them once PETSc holds them.
  MovableSpMat own =
      assemble_reduced_stiffness(md.mesh, md.material->tangent(Vec::Zero(voigt_size(d))), md.dofs, slab.owned_node);
  const SpMat& Kx = own;
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
    // A roller on a Γ3 node: 0 ≤ x_τ ≤ 0 keeps d unknowns per node (solver/solve.cpp does the same).
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

Engine::BandRows Engine::save_band() const {
  // The Γ3 rows this rank's model knows, sorted: every column of an owned row is a node of the
  // piece (with its ghosts), and no array of the global size is needed.
  std::vector<PetscInt> gamma3_rows;
  gamma3_rows.reserve(static_cast<size_t>(md.contact.size()) * static_cast<size_t>(d));
  for (Index k = 0; k < md.contact.size(); ++k)
    for (int c = 0; c < d; ++c) gamma3_rows.push_back(cdof(k) + c);
  std::sort(gamma3_rows.begin(), gamma3_rows.end());
  const auto on_gamma3 = [&](PetscInt j) { return std::binary_search(gamma3_rows.begin(), gamma3_rows.end(), j); };
  BandRows b;
  b.start.push_back(0);
  for (PetscInt i = lo; i < hi; ++i) {
    PetscInt nc;
    const PetscInt* cols;
    const PetscScalar* vals;
    HC_PETSC(MatGetRow(K.m, i, &nc, &cols, &vals));
    if (std::any_of(cols, cols + nc, on_gamma3)) {
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

}  // namespace hemicontact::petsc_engine::detail
