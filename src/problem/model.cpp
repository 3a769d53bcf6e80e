#include <hemicontact/problem/model.hpp>

#include <hemicontact/fem/nonlinear_assembly.hpp>

namespace hemicontact {

double Model::u_nu(const Vec& u, Index k) const {
  return u.segment(dim() * contact.node[k], dim()).dot(contact.normal.row(k).transpose());
}

Vec Model::internal_force(const Vec& u) const {
  return material->is_linear() ? Vec(K * u) : assemble_internal_force(mesh, *material, u);
}

double Model::elastic_energy(const Vec& u) const {
  return material->is_linear() ? 0.5 * u.dot(K * u) : assemble_elastic_energy(mesh, *material, u);
}

}  // namespace hemicontact
