#pragma once
/// @file assembly.hpp  Global assembly of the P1 stiffness matrix and load vector (full dofs).
///
/// Full dof numbering: node a, component i ↦ d·a + i. Dirichlet elimination and the local
/// (ν, τ) frames on Γ3 are applied afterwards by DofMap.

#include <hemicontact/fem/dof_map.hpp>
#include <hemicontact/material/material.hpp>
#include <hemicontact/mesh/mesh.hpp>

namespace hemicontact {

/// K = Σ_T |T| Bᵀ D B for a linear material (symmetric, full storage, N·d × N·d).
/// @throws Error if the material is not linear (use the nonlinear internal-force assembly).
SpMat assemble_stiffness(const Mesh& mesh, const Material& material);

/// K = Σ_T |T| Bᵀ D B for a constant Voigt matrix @p D (e.g. the Gram matrix of ∫ε(u):ε(v), whose
/// Voigt form with engineering shears is diag(1, 1, ½) in 2D).
SpMat assemble_stiffness(const Mesh& mesh, const Mat& D);

/// K_x = Tᵀ K T for a constant Voigt matrix @p D, assembled straight into the free dofs' pattern
/// (Γ1 and roller-held components never enter; Γ3 node blocks rotated into (ν, τ...) in place):
/// equal to dofs.reduce(assemble_stiffness(mesh, D)) without the full K, which at 2.1M dofs was a
/// 450 MB array assembled, reduced and freed.
/// @param col_lo, col_hi only the columns [col_lo, col_hi) are assembled (whole nodes; the others
/// stay empty): K_x is symmetric, so they are the rows a rank of the petsc engine owns,
/// and the node graph is built for those nodes only. Default: all.
MovableSpMat assemble_reduced_stiffness(const Mesh& mesh, const Mat& D, const DofMap& dofs, Index col_lo = 0,
                                        Index col_hi = -1);

/// The same, with the columns of the nodes marked in @p own_nodes (one flag per mesh node):
/// the rows a rank of the petsc engine owns after the graph partitioner moved them.
MovableSpMat assemble_reduced_stiffness(const Mesh& mesh, const Mat& D, const DofMap& dofs,
                                        const std::vector<char>& own_nodes);

/// The node graph of a mesh: each node's neighbours through the cells, sorted, itself included
/// (the sparsity of K with every entry a d×d block), compressed: node a's are nbr[ptr[a] ..
/// ptr[a + 1]). Only the nodes marked in @p keep (optional) get their lists, the others are empty:
/// a rank of the petsc engine holds its own nodes' graph (assembly, the partitioner's input).
struct NodeGraph {
  std::vector<Index> ptr;
  std::vector<int> nbr;
  const int* begin(Index a) const { return nbr.data() + ptr[a]; }
  const int* end(Index a) const { return nbr.data() + ptr[a + 1]; }
  Index size(Index a) const { return ptr[a + 1] - ptr[a]; }
};
NodeGraph node_graph(const Mesh& mesh, const std::vector<char>* keep = nullptr);

/// Body force: ∫Ω f0·φ_a = |T|/(d+1) f0 per cell node, exact for constant f0 and P1.
Vec assemble_body_force(const Mesh& mesh, const Vec& f0);

/// Tractions on Γ2 facets: ∫ f2·φ_a = |F|/d f2 per facet node, exact for piecewise-constant f2.
Vec assemble_tractions(const Mesh& mesh);

/// Cell-wise strains (Voigt, one row per cell) of the full displacement vector @p u.
RowMat cell_strains(const Mesh& mesh, const Vec& u);

/// Von Mises stress of a Voigt stress row (2D: plane components, σ33 taken as 0).
double von_mises(const Eigen::Ref<const Eigen::RowVectorXd>& s, int dim);

}  // namespace hemicontact
