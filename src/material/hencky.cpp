#include <hemicontact/material/hencky.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hemicontact {
namespace {

void require_positive(double v, const std::string& key, const std::string& what) {
  if (!(v > 0) || !std::isfinite(v)) {
    input_error(key + " = " + round_trip(v) + ": " + what + " must be a positive number");
  }
}

}  // namespace

Hencky::Hencky(double kappa, double mu0, double mu_inf, double eps_ref, int dim)
    : m_kappa(kappa), m_mu0(mu0), m_mu_inf(mu_inf), m_s0(eps_ref * eps_ref), m_dim(dim) {
  require_positive(kappa, "material (hencky) kappa", "the bulk modulus");
  require_positive(mu0, "material (hencky) mu_0", "the small-strain shear modulus");
  require_positive(mu_inf, "material.shear_ratio (hencky mu_inf)", "the large-strain shear modulus");
  require_positive(eps_ref, "material.eps_ref", "the reference deviatoric strain");
  if (dim != 2 && dim != 3) throw Error("Hencky: dim must be 2 (plane strain) or 3", EXIT_INTERNAL);
}

Hencky Hencky::from_young(double E, double nu, double shear_ratio, double eps_ref, int dim) {
  require_positive(E, "material.E", "Young's modulus");
  // κ = E/(3(1−2ν)) > 0 and μ_0 = E/(2(1+ν)) > 0 need −1 < ν < 1/2 (plane strain and 3D alike).
  if (!(nu > -1 && nu < 0.5)) {
    input_error("material.nu = " + round_trip(nu) + ": Poisson's ratio must lie in (-1, 0.5) for the hencky law");
  }
  require_positive(shear_ratio, "material.shear_ratio", "mu_inf/mu_0");
  const double mu0 = E / (2 * (1 + nu));
  return Hencky(E / (3 * (1 - 2 * nu)), mu0, shear_ratio * mu0, eps_ref, dim);
}

// μ(s) = μ_∞ + Δ (1 + s/s_0)^{-1/2},  Δ = μ_0 − μ_∞.
double Hencky::mu(double s) const { return m_mu_inf + (m_mu0 - m_mu_inf) / std::sqrt(1 + s / m_s0); }

// μ'(s) = −Δ/(2 s_0) (1 + s/s_0)^{-3/2}.
double Hencky::dmu(double s) const {
  const double r = 1 + s / m_s0;
  return -(m_mu0 - m_mu_inf) / (2 * m_s0 * r * std::sqrt(r));
}

// Φ(s) = μ_∞ s + 2Δ s_0 (√(1 + s/s_0) − 1), written as 2Δ s/(√(1 + s/s_0) + 1) to avoid the
// cancellation of √(1 + x) − 1 at small strains (the energy must be accurate to FD-test it).
double Hencky::Phi(double s) const { return m_mu_inf * s + 2 * (m_mu0 - m_mu_inf) * s / (std::sqrt(1 + s / m_s0) + 1); }

Vec Hencky::dev_voigt(const Vec& strain, double& tr) const {
  const int d = m_dim, nv = voigt_size(d);
  if (strain.size() != nv) throw Error("Hencky: strain of the wrong size", EXIT_INTERNAL);
  tr = strain.head(d).sum();  // ε33 = 0 in plane strain
  Vec dv(nv);
  for (int i = 0; i < d; ++i) dv[i] = strain[i] - tr / 3;
  for (int k = d; k < nv; ++k) dv[k] = 0.5 * strain[k];  // tensor shear ε_ij = γ_ij/2
  return dv;
}

double Hencky::norm2_of(const Vec& dv, double tr) const {
  double s = dv.head(m_dim).squaredNorm() + 2 * dv.tail(voigt_size(m_dim) - m_dim).squaredNorm();
  if (m_dim == 2) s += tr * tr / 9;  // (dev ε)_33 = −tr ε/3 in plane strain
  return s;
}

double Hencky::dev_norm2(const Vec& strain) const {
  double tr;
  const Vec dv = dev_voigt(strain, tr);
  return norm2_of(dv, tr);
}

double Hencky::energy_density(const Vec& strain) const {
  const double tr = strain.head(m_dim).sum();
  return 0.5 * m_kappa * tr * tr + Phi(dev_norm2(strain));
}

// ∂s/∂ε (Voigt, engineering shears) = 2 dv: normal i: 2 dev ε : ∂dev ε/∂ε_ii = 2 (dev ε)_ii since
// tr dev ε = 0 (also in plane strain, where (dev ε)_33 is counted); shear: ∂(2 ε_ij²)/∂γ_ij = γ_ij
// = 2 dv_k. Hence σ = κ tr ε m + Φ'(s) 2 dv, m = (1, .., 1, 0, .., 0).
Vec Hencky::stress(const Vec& strain) const {
  double tr;
  const Vec dv = dev_voigt(strain, tr);
  const double s = norm2_of(dv, tr);
  Vec sig = 2 * mu(s) * dv;
  sig.head(m_dim).array() += m_kappa * tr;
  return sig;
}

// ∂σ/∂ε = κ m mᵀ + 2μ(s) ∂dv/∂ε + 4μ'(s) dv dvᵀ, with ∂dv/∂ε = (I − m mᵀ/3) on the normal block and
// ½ on the shear diagonal. Symmetric by construction.
Mat Hencky::tangent(const Vec& strain) const {
  double tr;
  const Vec dv = dev_voigt(strain, tr);
  const double s = norm2_of(dv, tr);
  const int d = m_dim, nv = voigt_size(d);
  const double m = mu(s);
  Mat C = 4 * dmu(s) * dv * dv.transpose();
  for (int i = 0; i < d; ++i) {
    for (int j = 0; j < d; ++j) C(i, j) += m_kappa - 2 * m / 3;
    C(i, i) += 2 * m;
  }
  for (int k = d; k < nv; ++k) C(k, k) += m;
  return C;
}

// See the header: μ and ψ = μ + 2sμ' both lie in [μ_lo, μ_hi].
double Hencky::m_F() const {
  const double lo = std::min(m_mu0, m_mu_inf);
  return m_dim == 3 ? std::min(3 * m_kappa, 2 * lo) : std::min(2 * lo, 2 * m_kappa + 2 * lo / 3);
}

double Hencky::L_F() const {
  const double hi = std::max(m_mu0, m_mu_inf);
  return m_dim == 3 ? std::max(3 * m_kappa, 2 * hi) : std::max(2 * hi, 2 * m_kappa + 2 * hi / 3);
}

std::string Hencky::describe() const {
  std::ostringstream os;
  os << "hencky, " << (m_dim == 2 ? "plane strain" : "3D") << ", kappa = " << m_kappa << ", mu_0 = " << m_mu0
     << ", mu_inf = " << m_mu_inf << ", eps_ref = " << std::sqrt(m_s0)
     << " (mu(s) = mu_inf + (mu_0 - mu_inf)/sqrt(1 + s/eps_ref^2), s = |dev eps|^2)";
  return os.str();
}

}  // namespace hemicontact
