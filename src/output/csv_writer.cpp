#include <hemicontact/output/csv_writer.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/output/output_dir.hpp>

#include <charconv>
#include <limits>
#include <string>

namespace hemicontact {

Gamma3Row gamma3_row(const Model& md, const Solution& sol, Index k) {
  const ContactNodes& cn = md.contact;
  const ContactState& s = sol.state;
  Gamma3Row r;
  r.node = cn.node[k];
  for (int c = 0; c < md.dim(); ++c) r.p[c] = md.mesh.points(cn.node[k], c);
  r.w = cn.w[k];
  r.g = cn.g[k];
  r.u_nu = s.u_nu[k];
  r.u_tau = s.u_tau[k];
  r.sigma_nu = s.sigma_nu[k];
  r.sigma_tau = s.sigma_tau[k];
  r.xi = s.xi[k];
  r.lambda = s.lambda[k];
  r.status = sol.status[k];
  if (md.dim() == 3) {
    for (int c = 0; c < 3; ++c) r.slip_dir[c] = s.slip_dir(k, c);
    r.slip_angle_deg = s.slip_angle_deg[k];
  }
  return r;
}

void write_gamma3_csv(const std::string& path, const Model& md, const Solution& sol) {
  const Index nc = md.contact.size();
  if (sol.state.u_nu.size() != nc || static_cast<Index>(sol.status.size()) != nc)
    throw Error("write_gamma3_csv: the solution does not match the model (was evaluate_solution() called?)",
                EXIT_INTERNAL);
  std::vector<Gamma3Row> rows;
  std::vector<long> index;
  rows.reserve(static_cast<size_t>(nc));
  for (Index k = 0; k < nc; ++k) rows.push_back(gamma3_row(md, sol, k)), index.push_back(static_cast<long>(k));
  write_gamma3_csv(path, md.dim(), rows, index);
}

void write_gamma3_csv(const std::string& path, int d, const std::vector<Gamma3Row>& rows,
                      const std::vector<long>& index) {
  if (rows.size() != index.size()) throw Error("write_gamma3_csv: one index per row expected", EXIT_INTERNAL);
  std::string out = d == 2 ? "index,node,x,y," : "index,node,x,y,z,";
  // 2D columns are fixed (scripts read them); 3D appends the slip direction (NaN when sticking).
  out += "w,g,u_nu,u_tau,sigma_nu,sigma_tau,xi,lambda,status";
  out += d == 2 ? "\n" : ",slip_dir_x,slip_dir_y,slip_dir_z,slip_angle_deg\n";
  for (size_t q = 0; q < rows.size(); ++q) {
    const Gamma3Row& r = rows[q];
    out += std::to_string(index[q]) + ',' + std::to_string(r.node);
    for (int c = 0; c < d; ++c) {
      out += ',';
      append_round_trip(out, r.p[c]);
    }
    for (double v : {r.w, r.g, r.u_nu, r.u_tau, r.sigma_nu, r.sigma_tau, r.xi, r.lambda}) {
      out += ',';
      append_round_trip(out, v);
    }
    out += ',' + r.status.str();
    if (d == 3) {
      const bool slip = r.status.tangential == TangentialStatus::SLIP;
      const double nan = std::numeric_limits<double>::quiet_NaN();
      for (double v : {r.slip_dir[0], r.slip_dir[1], r.slip_dir[2], r.slip_angle_deg}) {
        out += ',';
        append_round_trip(out, slip ? v : nan);
      }
    }
    out += '\n';
  }

  write_text_file(path, out);
}

}  // namespace hemicontact
