#include <hemicontact/output/csv_writer.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/output/output_dir.hpp>

#include <charconv>
#include <limits>
#include <string>

namespace hemicontact {
void write_gamma3_csv(const std::string& path, const Model& md, const Solution& sol) {
  const ContactNodes& cn = md.contact;
  const ContactState& s = sol.state;
  const Index nc = cn.size();
  const int d = md.dim();
  if (s.u_nu.size() != nc || static_cast<Index>(sol.status.size()) != nc)
    throw Error("write_gamma3_csv: the solution does not match the model (was evaluate_solution() called?)",
                EXIT_INTERNAL);

  std::string out = d == 2 ? "index,node,x,y," : "index,node,x,y,z,";
  // 2D columns are fixed (scripts read them); 3D appends the slip direction (NaN when sticking).
  out += "w,g,u_nu,u_tau,sigma_nu,sigma_tau,xi,lambda,status";
  out += d == 2 ? "\n" : ",slip_dir_x,slip_dir_y,slip_dir_z,slip_angle_deg\n";
  for (Index k = 0; k < nc; ++k) {
    out += std::to_string(k) + ',' + std::to_string(cn.node[k]);
    for (int c = 0; c < d; ++c) {
      out += ',';
      append_round_trip(out, md.mesh.points(cn.node[k], c));
    }
    for (double v : {cn.w[k], cn.g[k], s.u_nu[k], s.u_tau[k], s.sigma_nu[k], s.sigma_tau[k], s.xi[k], s.lambda[k]}) {
      out += ',';
      append_round_trip(out, v);
    }
    out += ',' + sol.status[k].str();
    if (d == 3) {
      const bool slip = sol.status[k].tangential == TangentialStatus::SLIP;
      const double nan = std::numeric_limits<double>::quiet_NaN();
      for (double v : {s.slip_dir(k, 0), s.slip_dir(k, 1), s.slip_dir(k, 2), s.slip_angle_deg[k]}) {
        out += ',';
        append_round_trip(out, slip ? v : nan);
      }
    }
    out += '\n';
  }

  write_text_file(path, out);
}

}  // namespace hemicontact
