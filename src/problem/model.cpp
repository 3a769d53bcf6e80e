#include <hemicontact/problem/model.hpp>

#include <hemicontact/fem/nonlinear_assembly.hpp>

namespace hemicontact {

double Model::u_nu(const Vec& u, Index k) const {
  return u.segment(dim() * contact.node[k], dim()).dot(contact.normal.row(k).transpose());
}

Vec Model::internal_force(const Vec& u) const {
  if (!material->is_linear()) return assemble_internal_force(mesh, *material, u);
  if (Kx_apply) return dofs.to_full(Kx_apply(dofs.to_reduced(u)));
  return dofs.to_full(Kx * dofs.to_reduced(u));
}

double Model::elastic_energy(const Vec& u) const {
  return material->is_linear() ? 0.5 * a(u, u) : assemble_elastic_energy(mesh, *material, u);
}

double Model::a(const Vec& u, const Vec& v) const {
  const Vec x = dofs.to_reduced(u);
  if (Kx_apply) return x.dot(Kx_apply(&u == &v ? x : dofs.to_reduced(v)));
  return &u == &v ? x.dot(Kx * x) : x.dot(Kx * dofs.to_reduced(v));
}

}  // namespace hemicontact
