#include <hemicontact/material/linear_elastic.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hemicontact {

LinearElastic::LinearElastic(double E, double nu, PlaneMode mode) : m_E(E), m_nu(nu), m_mode(mode) {
  if (!(E > 0) || !std::isfinite(E)) input_error("material.E must be a positive number, got " + round_trip(E));
  // ν ≥ 0.5 makes the plane-strain/3D law singular (incompressible) and is unphysical in plane
  // stress too (no isotropic 3D material has it); ν ≤ −1 loses positivity.
  if (!(nu > -1 && nu < 0.5)) {
    input_error("material.nu = " + round_trip(nu) + ": Poisson's ratio must lie in (-1, 0.5)" +
                (mode == PlaneMode::STRESS ? "" : " (plane strain/3D: the law is singular at 0.5)"));
  }
  if (mode == PlaneMode::STRESS) {
    m_a = E * nu / (1 - nu * nu);
  } else {
    m_a = E * nu / ((1 + nu) * (1 - 2 * nu));
  }
  m_b = E / (1 + nu);
  const int d = dim(), nv = voigt_size(d);
  m_D = Mat::Zero(nv, nv);
  for (int i = 0; i < d; ++i) {
    for (int j = 0; j < d; ++j) m_D(i, j) = m_a;
    m_D(i, i) += m_b;
  }
  // Engineering shear γ = 2ε: σ12 = b ε12 = (b/2) γ12.
  for (int k = d; k < nv; ++k) m_D(k, k) = m_b / 2;
}

double LinearElastic::energy_density(const Vec& strain) const { return 0.5 * strain.dot(m_D * strain); }
Vec LinearElastic::stress(const Vec& strain) const { return m_D * strain; }
double LinearElastic::m_F() const { return std::min(m_b, m_b + dim() * m_a); }
double LinearElastic::L_F() const { return std::max(m_b, m_b + dim() * m_a); }

std::string LinearElastic::describe() const {
  std::ostringstream os;
  os << "linear elastic, "
     << (m_mode == PlaneMode::STRESS   ? "plane stress"
         : m_mode == PlaneMode::STRAIN ? "plane strain"
                                       : "3D")
     << ", E = " << m_E << ", nu = " << m_nu;
  return os.str();
}

}  // namespace hemicontact
