#include <hemicontact/output/vtk_writer.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/output/output_dir.hpp>

#include <charconv>
#include <functional>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

// Shortest text that reads back to the same double: exact and diff-friendly.
void put(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

void check_sizes(const Model& md, const Solution& sol) {
  const Index nc = md.contact.size();
  if (sol.u.size() != md.dofs.n_full() || sol.state.u_nu.size() != nc ||
      static_cast<Index>(sol.status.size()) != nc)
    throw Error("write_vtu: the solution does not match the model (was evaluate_solution() called?)",
                EXIT_INTERNAL);
}

void open_array(std::string& out, const char* type, const std::string& name, int comps) {
  out += "        <DataArray type=\"";
  out += type;
  out += "\"";
  if (!name.empty()) out += " Name=\"" + name + "\"";
  out += " NumberOfComponents=\"" + std::to_string(comps) + "\" format=\"ascii\">\n";
}

// A Float64 array of @p rows tuples with @p comps components each, one tuple per line.
void float_array(std::string& out, const std::string& name, Index rows, int comps,
                 const std::function<double(Index, int)>& value) {
  open_array(out, "Float64", name, comps);
  for (Index r = 0; r < rows; ++r) {
    out += "          ";
    for (int c = 0; c < comps; ++c) {
      if (c) out += ' ';
      put(out, value(r, c));
    }
    out += '\n';
  }
  out += "        </DataArray>\n";
}

void int_array(std::string& out, const char* type, const std::string& name, const std::vector<long long>& v,
               int per_line) {
  open_array(out, type, name, 1);
  for (size_t i = 0; i < v.size(); ++i) {
    out += (i % per_line == 0) ? "          " : " ";
    out += std::to_string(v[i]);
    if ((i + 1) % per_line == 0 || i + 1 == v.size()) out += '\n';
  }
  out += "        </DataArray>\n";
}

}  // namespace

int status_code(NormalStatus s) {
  switch (s) {
    case NormalStatus::SEPARATED: return 0;
    case NormalStatus::COMPLIANCE: return 1;
    case NormalStatus::CONTACT: return 2;
  }
  return -1;
}

int status_code(TangentialStatus s) {
  switch (s) {
    case TangentialStatus::STICK: return 0;
    case TangentialStatus::SLIP_PLUS: return 1;
    case TangentialStatus::SLIP_MINUS: return 2;
    case TangentialStatus::SLIP: return 3;
  }
  return -1;
}

void write_vtu(const std::string& path, const Model& md, const Solution& sol) {
  check_sizes(md, sol);
  const Mesh& mesh = md.mesh;
  const int d = mesh.dim, nv = voigt_size(d);
  const Index N = mesh.num_nodes(), M = mesh.num_cells(), nc = md.contact.size();
  const ContactState& s = sol.state;

  // Γ3 quantities scattered to mesh nodes (k_of[a] = contact index or −1).
  std::vector<Index> k_of(N, -1);
  for (Index k = 0; k < nc; ++k) k_of[md.contact.node[k]] = k;
  const auto on_gamma3 = [&](const Vec& v) {
    return [&, v_ptr = &v](Index a, int) { return k_of[a] < 0 ? 0.0 : (*v_ptr)[k_of[a]]; };
  };
  const auto tangential = [&](const RowMat& m) {
    return [&, m_ptr = &m](Index a, int c) {
      return (k_of[a] < 0 || c >= m_ptr->cols()) ? 0.0 : (*m_ptr)(k_of[a], c);
    };
  };

  const RowMat strain = cell_strains(mesh, sol.u);
  RowMat stress(M, nv);
  Vec vm(M);
  for (Index c = 0; c < M; ++c) {
    stress.row(c) = md.material->stress(strain.row(c).transpose()).transpose();
    vm[c] = von_mises(stress.row(c), d);
  }

  std::string out;
  out.reserve(static_cast<size_t>(N) * 400 + static_cast<size_t>(M) * 300);
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  out += "  <UnstructuredGrid>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(N) + "\" NumberOfCells=\"" + std::to_string(M) + "\">\n";

  out += "      <PointData Scalars=\"status_normal\" Vectors=\"displacement\">\n";
  float_array(out, "displacement", N, 3, [&](Index a, int c) { return c < d ? sol.u[d * a + c] : 0.0; });
  std::vector<long long> mask(N), sn(N, -1), st(N, -1);
  for (Index a = 0; a < N; ++a) mask[a] = k_of[a] >= 0;
  for (Index k = 0; k < nc; ++k) {
    sn[md.contact.node[k]] = status_code(sol.status[k].normal);
    st[md.contact.node[k]] = status_code(sol.status[k].tangential);
  }
  int_array(out, "Int32", "gamma3", mask, 20);
  float_array(out, "u_nu", N, 1, on_gamma3(s.u_nu));
  float_array(out, "u_tau", N, 1, on_gamma3(s.u_tau));
  float_array(out, "sigma_nu", N, 1, on_gamma3(s.sigma_nu));
  float_array(out, "sigma_tau", N, 1, on_gamma3(s.sigma_tau));
  float_array(out, "xi", N, 1, on_gamma3(s.xi));
  float_array(out, "lambda", N, 1, on_gamma3(s.lambda));
  float_array(out, "u_tau_vec", N, 3, tangential(s.u_tau_vec));
  float_array(out, "sigma_tau_vec", N, 3, tangential(s.sigma_tau_vec));
  if (d == 3) {
    // 3D: unit slip direction and its angle (zero on sticking and non-Γ3 nodes); 2D has slip±.
    RowMat dir = RowMat::Zero(nc, 3);
    Vec angle = Vec::Zero(nc);
    for (Index k = 0; k < nc; ++k)
      if (sol.status[k].tangential == TangentialStatus::SLIP) {
        dir.row(k) = s.slip_dir.row(k);
        angle[k] = s.slip_angle_deg[k];
      }
    float_array(out, "slip_dir", N, 3, [&](Index a, int c) { return k_of[a] < 0 ? 0.0 : dir(k_of[a], c); });
    float_array(out, "slip_angle_deg", N, 1, [&](Index a, int) { return k_of[a] < 0 ? 0.0 : angle[k_of[a]]; });
  }
  int_array(out, "Int32", "status_normal", sn, 20);
  int_array(out, "Int32", "status_tangential", st, 20);
  out += "      </PointData>\n";

  out += "      <CellData Scalars=\"von_mises\">\n";
  float_array(out, "strain", M, nv, [&](Index c, int i) { return strain(c, i); });
  float_array(out, "stress", M, nv, [&](Index c, int i) { return stress(c, i); });
  float_array(out, "von_mises", M, 1, [&](Index c, int) { return vm[c]; });
  out += "      </CellData>\n";

  out += "      <Points>\n";
  float_array(out, "Points", N, 3, [&](Index a, int c) { return c < d ? mesh.points(a, c) : 0.0; });
  out += "      </Points>\n";

  out += "      <Cells>\n";
  std::vector<long long> conn, offsets(M), types(M, d == 2 ? 5 : 10);
  conn.reserve(static_cast<size_t>(M) * (d + 1));
  for (Index c = 0; c < M; ++c) {
    for (int a = 0; a <= d; ++a) conn.push_back(mesh.cells(c, a));
    offsets[c] = static_cast<long long>((c + 1) * (d + 1));
  }
  int_array(out, "Int64", "connectivity", conn, d + 1);
  int_array(out, "Int64", "offsets", offsets, 20);
  int_array(out, "UInt8", "types", types, 20);
  out += "      </Cells>\n";
  out += "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";

  write_text_file(path, out);
}

}  // namespace hemicontact
