#include <hemicontact/problem/model.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/nonlinear_assembly.hpp>

namespace hemicontact {

double Model::u_nu(const Vec& u, Index k) const {
  return u.segment(dim() * contact.node[k], dim()).dot(contact.normal.row(k).transpose());
}

namespace {

// A model built without K_x (the petsc engine's) cannot apply it: its rows live in PETSc.
void require_stiffness(const Model& md) {
  if (md.Kx.empty() && md.dofs.n_free() > 0)
    throw Error("this model keeps no K_x (built for the petsc engine, which holds its rows)", EXIT_INTERNAL);
}

}  // namespace

Vec Model::internal_force(const Vec& u) const {
  if (!material->is_linear()) return assemble_internal_force(mesh, *material, u);
  require_stiffness(*this);
  return dofs.to_full(Kx * dofs.to_reduced(u));
}

double Model::elastic_energy(const Vec& u) const {
  return material->is_linear() ? 0.5 * a(u, u) : assemble_elastic_energy(mesh, *material, u);
}

double Model::a(const Vec& u, const Vec& v) const {
  require_stiffness(*this);
  const Vec x = dofs.to_reduced(u);
  return &u == &v ? x.dot(Kx * x) : x.dot(Kx * dofs.to_reduced(v));
}

}  // namespace hemicontact
