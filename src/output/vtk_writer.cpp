#include <hemicontact/output/vtk_writer.hpp>
#include <hemicontact/output/pvtu_writer.hpp>

#include <hemicontact/config.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/output/output_dir.hpp>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <functional>
#include <string>
#include <tuple>
#include <cstring>
#include <system_error>
#include <thread>
#include <vector>

#if HEMICONTACT_HAS_ZLIB
#include <zlib.h>
#endif

namespace hemicontact {
namespace {

void check_sizes(const Model& md, const Solution& sol) {
  const Index nc = md.contact.size();
  if (sol.u.size() != md.dofs.n_full() || sol.state.u_nu.size() != nc || static_cast<Index>(sol.status.size()) != nc)
    throw Error("write_vtu: the solution does not match the model (was evaluate_solution() called?)", EXIT_INTERNAL);
}

// One DataArray, kept as typed values until the file is laid out (ASCII inline, or binary in the
// appended block).
struct Array {
  std::string type;  // "Float64", "Int32", "Int64", "UInt8"
  std::string name;
  int comps = 1;
  std::vector<double> f;     // Float64 values
  std::vector<long long> i;  // integer values
};

Array float_array(const std::string& name, Index rows, int comps, const std::function<double(Index, int)>& value) {
  Array a{"Float64", name, comps, {}, {}};
  a.f.reserve(static_cast<size_t>(rows) * comps);
  for (Index r = 0; r < rows; ++r)
    for (int c = 0; c < comps; ++c) a.f.push_back(value(r, c));
  return a;
}

Array int_array(const char* type, const std::string& name, std::vector<long long> v) {
  return Array{type, name, 1, {}, std::move(v)};
}

// The raw little-endian bytes of an array (x86-64 and ARM64 are little-endian; the file says so).
// The array's values as raw little-endian bytes of its VTK type. Written into a string sized
// once (one append per value was a quarter of the VTU writing time at n = 256).
template <class T, class Source>
std::string raw_bytes(const Source& values) {
  std::string b(values.size() * sizeof(T), '\0');
  char* dst = b.data();
  for (const auto v : values) {
    const T t = static_cast<T>(v);
    std::memcpy(dst, &t, sizeof t);
    dst += sizeof t;
  }
  return b;
}

std::string bytes_of(const Array& a) {
  if (a.type == "Float64") return raw_bytes<double>(a.f);
  if (a.type == "Int64") return raw_bytes<std::int64_t>(a.i);
  if (a.type == "Int32") return raw_bytes<std::int32_t>(a.i);
  return raw_bytes<std::uint8_t>(a.i);
}

void put_u64(std::string& out, std::uint64_t v) { out.append(reinterpret_cast<const char*>(&v), 8); }

// zlib level of an array. Level 1 gets most of zlib's gain at a fraction of its default's time;
// but dense Float64 arrays (points, displacements, stresses) shrink only ~1.5x for 4x the time of
// everything else in the file, so they are stored (level 0: zlib's framing, no search). Arrays
// that are mostly zeros (the Γ3 fields, the 0/1 status fields, integer connectivity) shrink
// 10-100x, fast. Measured at n = 256: 11.3 MB in 0.06 s instead of 7.2 MB in 0.12 s.
int zlib_level(const Array& a) {
  if (a.type != "Float64") return 1;
  const auto zeros = std::count(a.f.begin(), a.f.end(), 0.0);
  return 2 * static_cast<size_t>(zeros) >= a.f.size() ? 1 : 0;
}

// One array's appended block: VTK's layout for header_type UInt64. Uncompressed: [nbytes] data.
// Compressed (vtkZLibDataCompressor): [nblocks, block size, size of the last block (0: full),
// compressed size of each block] then the compressed blocks.
std::string appended_block(const std::string& raw, bool compress, int level) {
  std::string out;
#if HEMICONTACT_HAS_ZLIB
  if (compress) {
    constexpr std::uint64_t BLOCK = 1 << 15;  // VTK's default block size
    const std::uint64_t n = raw.size(), nblocks = n == 0 ? 0 : (n + BLOCK - 1) / BLOCK;
    std::vector<std::string> blocks(nblocks);
    std::vector<char> failed(nblocks, 0);
    const auto compress_blocks = [&](std::uint64_t first, std::uint64_t stride) {
      for (std::uint64_t k = first; k < nblocks; k += stride) {
        const std::uint64_t len = std::min<std::uint64_t>(BLOCK, n - k * BLOCK);
        uLongf cap = compressBound(static_cast<uLong>(len));
        std::string& c = blocks[k];
        c.assign(cap, '\0');
        failed[k] = compress2(reinterpret_cast<Bytef*>(c.data()), &cap,
                              reinterpret_cast<const Bytef*>(raw.data() + k * BLOCK), static_cast<uLong>(len),
                              level) != Z_OK;
        c.resize(cap);
      }
    };
    // The blocks are independent: compressed on every core (output is then a few % of the run, not
    // 15%); the file is the same whatever the number of threads.
    const std::uint64_t threads =
        std::min<std::uint64_t>({std::max(1u, std::thread::hardware_concurrency()), 8, (nblocks + 7) / 8});
    const std::uint64_t stride = std::max<std::uint64_t>(threads, 1);
    std::vector<std::thread> pool;
    std::uint64_t started = 1;
    // A thread that cannot be created (EAGAIN: under ulimit -v its stack may not fit) leaves its
    // share of the blocks to this one; the vector must not be destroyed with joinable threads
    // (std::terminate).
    try {
      for (; started < threads; ++started) pool.emplace_back(compress_blocks, started, stride);
    } catch (const std::system_error&) {
    }
    for (std::uint64_t t = started; t < threads; ++t) compress_blocks(t, stride);
    compress_blocks(0, stride);
    for (auto& th : pool) th.join();
    if (std::find(failed.begin(), failed.end(), 1) != failed.end())
      throw Error("write_vtu: zlib compression failed", EXIT_INTERNAL);
    put_u64(out, nblocks);
    put_u64(out, BLOCK);
    put_u64(out, n % BLOCK);
    for (const auto& c : blocks) put_u64(out, c.size());
    for (const auto& c : blocks) out += c;
    return out;
  }
#endif
  (void)compress;
  put_u64(out, raw.size());
  out += raw;
  return out;
}

// Lays the arrays out as XML, inline (ASCII) or as references into the appended block (binary).
class VtuLayout {
 public:
  explicit VtuLayout(bool binary) : m_binary(binary) {}
  void array(std::string& xml, const Array& a) {
    xml += "        <DataArray type=\"" + a.type + "\"";
    if (!a.name.empty()) xml += " Name=\"" + a.name + "\"";
    xml += " NumberOfComponents=\"" + std::to_string(a.comps) + "\"";
    if (m_binary) {
      xml += " format=\"appended\" offset=\"" + std::to_string(m_appended.size()) + "\"/>\n";
      m_appended += appended_block(bytes_of(a), HEMICONTACT_HAS_ZLIB != 0, zlib_level(a));
      return;
    }
    xml += " format=\"ascii\">\n";
    const size_t n = a.type == "Float64" ? a.f.size() : a.i.size();
    const size_t per_line = a.type == "Float64" ? static_cast<size_t>(a.comps) : (a.name == "connectivity" ? 4 : 20);
    for (size_t k = 0; k < n; ++k) {
      xml += (k % per_line == 0) ? "          " : " ";
      if (a.type == "Float64")
        append_round_trip(xml, a.f[k]);
      else
        xml += std::to_string(a.i[k]);
      if ((k + 1) % per_line == 0 || k + 1 == n) xml += '\n';
    }
    xml += "        </DataArray>\n";
  }
  /// The whole file: the header's compressor attribute, the XML, then the appended block.
  std::string finish(const std::string& body) const {
    std::string out =
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
        "byte_order=\"LittleEndian\" header_type=\"UInt64\"";
    if (m_binary && HEMICONTACT_HAS_ZLIB) out += " compressor=\"vtkZLibDataCompressor\"";
    out += ">\n" + body;
    if (m_binary) out += "  <AppendedData encoding=\"raw\">\n   _" + m_appended + "\n  </AppendedData>\n";
    out += "</VTKFile>\n";
    return out;
  }

 private:
  bool m_binary;
  std::string m_appended;
};

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

namespace {

// The legend of the integer status codes (status_code above).
const char* const STATUS_LEGEND =
    "status_normal: -1 not on Gamma3, 0 separated, 1 compliance, 2 contact; status_tangential: -1 not on "
    "Gamma3, 0 stick, 1 slip+, 2 slip-, 3 slip (3D)";

// The legend as field data, readable in ParaView's information panel.
void write_field_data(VtuLayout& L, std::string& xml) {
  xml += "    <FieldData>\n";
  const std::string legend = STATUS_LEGEND;
  std::vector<long long> chars(legend.begin(), legend.end());
  Array leg = int_array("UInt8", "status_legend", chars);
  leg.comps = static_cast<int>(chars.size());
  xml += "      <!-- " + legend + " -->\n";
  L.array(xml, leg);
  xml += "    </FieldData>\n";
}

// The statuses: integer codes (legend in write_field_data), and every status as its own 0/1 field
// (ParaView colours by name).
void write_status_fields(VtuLayout& L, std::string& xml, const Model& md, const Solution& sol) {
  const int d = md.mesh.dim;
  const Index N = md.mesh.num_nodes(), nc = md.contact.size();
  std::vector<long long> sn(N, -1), st(N, -1);
  for (Index k = 0; k < nc; ++k) {
    sn[md.contact.node[k]] = status_code(sol.status[k].normal);
    st[md.contact.node[k]] = status_code(sol.status[k].tangential);
  }
  L.array(xml, int_array("Int32", "status_normal", sn));
  L.array(xml, int_array("Int32", "status_tangential", st));
  const std::vector<std::pair<std::string, std::function<bool(const NodeStatus&)>>> by_name = {
      {"separated", [](const NodeStatus& t) { return t.normal == NormalStatus::SEPARATED; }},
      {"compliance", [](const NodeStatus& t) { return t.normal == NormalStatus::COMPLIANCE; }},
      {"contact", [](const NodeStatus& t) { return t.normal == NormalStatus::CONTACT; }},
      {"stick", [](const NodeStatus& t) { return t.tangential == TangentialStatus::STICK; }},
      {"slip_plus", [](const NodeStatus& t) { return t.tangential == TangentialStatus::SLIP_PLUS; }},
      {"slip_minus", [](const NodeStatus& t) { return t.tangential == TangentialStatus::SLIP_MINUS; }},
      {"slip", [](const NodeStatus& t) { return t.tangential == TangentialStatus::SLIP; }}};
  for (const auto& [name, is] : by_name) {
    if ((name == "slip") != (d == 3) && (name == "slip" || name == "slip_plus" || name == "slip_minus")) continue;
    std::vector<long long> v(N, 0);
    for (Index k = 0; k < nc; ++k) v[md.contact.node[k]] = is(sol.status[k]) ? 1 : 0;
    L.array(xml, int_array("UInt8", name, v));
  }
}

// Nodal fields: the displacement, and the Γ3 quantities scattered to mesh nodes (zero elsewhere).
void write_point_data(VtuLayout& L, std::string& xml, const Model& md, const Solution& sol) {
  const int d = md.mesh.dim;
  const Index N = md.mesh.num_nodes(), nc = md.contact.size();
  const ContactState& s = sol.state;
  // k_of[a] = contact index or −1.
  std::vector<Index> k_of(N, -1);
  for (Index k = 0; k < nc; ++k) k_of[md.contact.node[k]] = k;
  const auto on_gamma3 = [&](const Vec& v) {
    return [&, v_ptr = &v](Index a, int) { return k_of[a] < 0 ? 0.0 : (*v_ptr)[k_of[a]]; };
  };
  const auto tangential = [&](const RowMat& m) {
    return [&, m_ptr = &m](Index a, int c) { return (k_of[a] < 0 || c >= m_ptr->cols()) ? 0.0 : (*m_ptr)(k_of[a], c); };
  };
  xml += "      <PointData Scalars=\"status_normal\" Vectors=\"displacement\">\n";
  L.array(xml, float_array("displacement", N, 3, [&](Index a, int c) { return c < d ? sol.u[d * a + c] : 0.0; }));
  std::vector<long long> mask(N);
  for (Index a = 0; a < N; ++a) mask[a] = k_of[a] >= 0;
  L.array(xml, int_array("Int32", "gamma3", mask));
  L.array(xml, float_array("u_nu", N, 1, on_gamma3(s.u_nu)));
  L.array(xml, float_array("u_tau", N, 1, on_gamma3(s.u_tau)));
  L.array(xml, float_array("sigma_nu", N, 1, on_gamma3(s.sigma_nu)));
  L.array(xml, float_array("sigma_tau", N, 1, on_gamma3(s.sigma_tau)));
  L.array(xml, float_array("xi", N, 1, on_gamma3(s.xi)));
  L.array(xml, float_array("lambda", N, 1, on_gamma3(s.lambda)));
  L.array(xml, float_array("u_tau_vec", N, 3, tangential(s.u_tau_vec)));
  L.array(xml, float_array("sigma_tau_vec", N, 3, tangential(s.sigma_tau_vec)));
  if (d == 3) {
    // 3D: unit slip direction and its angle (zero on sticking and non-Γ3 nodes); 2D has slip±.
    RowMat dir = RowMat::Zero(nc, 3);
    Vec angle = Vec::Zero(nc);
    for (Index k = 0; k < nc; ++k)
      if (sol.status[k].tangential == TangentialStatus::SLIP) {
        dir.row(k) = s.slip_dir.row(k);
        angle[k] = s.slip_angle_deg[k];
      }
    L.array(xml, float_array("slip_dir", N, 3, [&](Index a, int c) { return k_of[a] < 0 ? 0.0 : dir(k_of[a], c); }));
    L.array(xml, float_array("slip_angle_deg", N, 1, [&](Index a, int) { return k_of[a] < 0 ? 0.0 : angle[k_of[a]]; }));
  }
  write_status_fields(L, xml, md, sol);
  xml += "      </PointData>\n";
}

// Cell fields: strain, stress (the material's), von Mises, and the error indicator when given.
// The cells written: @p cells (a piece's own), or all.
struct CellList {
  const std::vector<Index>* cells;
  Index all;
  Index size() const { return cells ? static_cast<Index>(cells->size()) : all; }
  Index operator[](Index r) const { return cells ? (*cells)[static_cast<size_t>(r)] : r; }
};

void write_cell_data(VtuLayout& L, std::string& xml, const Model& md, const Solution& sol,
                     const Vec* error_indicator, const CellList& C) {
  const Index M = C.size();
  const int nv = voigt_size(md.mesh.dim);
  const CellFields f = cell_fields(md, sol);
  const RowMat &strain = f.strain, &stress = f.stress;
  const Vec& vm = f.von_mises;
  xml += "      <CellData Scalars=\"von_mises\">\n";
  L.array(xml, float_array("strain", M, nv, [&](Index r, int i) { return strain(C[r], i); }));
  L.array(xml, float_array("stress", M, nv, [&](Index r, int i) { return stress(C[r], i); }));
  L.array(xml, float_array("von_mises", M, 1, [&](Index r, int) { return vm[C[r]]; }));
  if (error_indicator && error_indicator->size() > 0)
    L.array(xml, float_array("error_indicator", M, 1, [&](Index r, int) { return (*error_indicator)[C[r]]; }));
  xml += "      </CellData>\n";
}
void write_points_and_cells(VtuLayout& L, std::string& xml, const Mesh& mesh, const CellList& C) {
  const int d = mesh.dim;
  const Index N = mesh.num_nodes(), M = C.size();
  xml += "      <Points>\n";
  L.array(xml, float_array("Points", N, 3, [&](Index a, int c) { return c < d ? mesh.points(a, c) : 0.0; }));
  xml += "      </Points>\n";

  xml += "      <Cells>\n";
  std::vector<long long> conn, offsets(M), types(M, d == 2 ? 5 : 10);
  conn.reserve(static_cast<size_t>(M) * (d + 1));
  for (Index c = 0; c < M; ++c) {
    for (int a = 0; a <= d; ++a) conn.push_back(mesh.cells(C[c], a));
    offsets[c] = static_cast<long long>((c + 1) * (d + 1));
  }
  L.array(xml, int_array("Int64", "connectivity", conn));
  L.array(xml, int_array("Int64", "offsets", offsets));
  L.array(xml, int_array("UInt8", "types", types));
  xml += "      </Cells>\n";
}

}  // namespace

CellFields cell_fields(const Model& md, const Solution& sol) {
  const Mesh& mesh = md.mesh;
  const int d = mesh.dim, nv = voigt_size(d);
  const Index M = mesh.num_cells();
  CellFields f;
  f.strain = cell_strains(mesh, sol.u);
  f.stress.resize(M, nv);
  f.von_mises.resize(M);
  for (Index c = 0; c < M; ++c) {
    f.stress.row(c) = md.material->stress(f.strain.row(c).transpose()).transpose();
    f.von_mises[c] = von_mises(f.stress.row(c), d);
  }
  return f;
}

void write_vtu(const std::string& path, const Model& md, const Solution& sol, VtuFormat format,
               const Vec* error_indicator, const std::vector<Index>* cells) {
  check_sizes(md, sol);
  if (error_indicator && error_indicator->size() > 0 && error_indicator->size() != md.mesh.num_cells())
    throw Error("write_vtu: " + std::to_string(error_indicator->size()) + " error indicators for " +
                    std::to_string(md.mesh.num_cells()) + " cells",
                EXIT_INTERNAL);
  const Mesh& mesh = md.mesh;
  const CellList C{cells, mesh.num_cells()};
  VtuLayout L(format == VtuFormat::BINARY);
  std::string xml;
  xml += "  <UnstructuredGrid>\n";
  write_field_data(L, xml);
  xml += "    <Piece NumberOfPoints=\"" + std::to_string(mesh.num_nodes()) + "\" NumberOfCells=\"" +
         std::to_string(C.size()) + "\">\n";
  write_point_data(L, xml, md, sol);
  write_cell_data(L, xml, md, sol, error_indicator, C);
  write_points_and_cells(L, xml, mesh, C);
  xml += "    </Piece>\n  </UnstructuredGrid>\n";
  const std::string out = L.finish(xml);

  write_text_file(path, out);
}

void write_pvtu(const std::string& path, int dim, const std::vector<std::string>& pieces) {
  // The arrays of write_point_data, write_status_fields and write_cell_data, in their order
  // (name, type, components); a test compares them with a piece's.
  const int nv = voigt_size(dim);
  std::vector<std::tuple<std::string, std::string, int>> point = {
      {"displacement", "Float64", 3}, {"gamma3", "Int32", 1},        {"u_nu", "Float64", 1},
      {"u_tau", "Float64", 1},        {"sigma_nu", "Float64", 1},    {"sigma_tau", "Float64", 1},
      {"xi", "Float64", 1},           {"lambda", "Float64", 1},      {"u_tau_vec", "Float64", 3},
      {"sigma_tau_vec", "Float64", 3}};
  if (dim == 3) point.insert(point.end(), {{"slip_dir", "Float64", 3}, {"slip_angle_deg", "Float64", 1}});
  point.insert(point.end(), {{"status_normal", "Int32", 1}, {"status_tangential", "Int32", 1}, {"separated", "UInt8", 1},
                             {"compliance", "UInt8", 1}, {"contact", "UInt8", 1}, {"stick", "UInt8", 1}});
  if (dim == 3)
    point.emplace_back("slip", "UInt8", 1);
  else
    point.insert(point.end(), {{"slip_plus", "UInt8", 1}, {"slip_minus", "UInt8", 1}});
  const std::vector<std::tuple<std::string, std::string, int>> cell = {
      {"strain", "Float64", nv}, {"stress", "Float64", nv}, {"von_mises", "Float64", 1}};
  const auto arrays = [](std::string& out, const std::vector<std::tuple<std::string, std::string, int>>& list) {
    for (const auto& [name, type, comps] : list)
      out += "      <PDataArray type=\"" + type + "\" Name=\"" + name + "\" NumberOfComponents=\"" +
             std::to_string(comps) + "\"/>\n";
  };
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n"
      "    <!-- " + std::string(STATUS_LEGEND) + " (each piece's field data status_legend) -->\n"
      "    <PPointData Scalars=\"status_normal\" Vectors=\"displacement\">\n";
  arrays(out, point);
  out += "    </PPointData>\n    <PCellData Scalars=\"von_mises\">\n";
  arrays(out, cell);
  out += "    </PCellData>\n    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
         "    </PPoints>\n";
  for (const std::string& p : pieces) out += "    <Piece Source=\"" + p + "\"/>\n";
  out += "  </PUnstructuredGrid>\n</VTKFile>\n";
  write_text_file(path, out);
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& entries) {
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const auto& [t, file] : entries) {
    out += "    <DataSet timestep=\"";
    append_round_trip(out, t);
    out += "\" part=\"0\" file=\"" + file + "\"/>\n";
  }
  out += "  </Collection>\n</VTKFile>\n";
  write_text_file(path, out);
}

}  // namespace hemicontact
