// Tests of the writers (VTU, Γ3 CSV, JSON report, stdout summary) and of the output directory
// guard. The Solution is made by hand (a prescribed displacement, then evaluate_solution()), so
// no NLP backend runs: the writers are checked against the Solution they were given.

#include <hemicontact/output/csv_writer.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/output/vtk_writer.hpp>

#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include "../support/expect_error.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

#if HEMICONTACT_HAS_ZLIB
#include <zlib.h>
#endif

namespace hemicontact {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

/// The scene of the brief: a 4×4 square on a soft layer with the paper's law (32).
json test_scene(int n = 4) {
  json s = json::parse(R"({
    "mesh": {"n": 4}, "material": {"E": 2000, "nu": 0.4},
    "boundary": {"gamma1": [{"side": "top"}],
                 "gamma2": [{"side": "left", "from": 0.5, "traction": [8e-3, 0]}],
                 "gamma3": [{"side": "bottom"}]},
    "loads": {"body_force": [0, -5e-4]},
    "contact": {"gap": 0.15,
                "normal_law": {"type": "paper", "c1": 100, "c2": -100, "c3": 400, "r1": 0.1, "r2": 0.15},
                "friction": {"type": "coulomb_layer", "mu": 0.2}}})");
  s["mesh"]["n"] = n;
  return validate_scene(s);
}

/// A fresh empty directory under the system temp dir, removed at the end of the test.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name) {
    path = fs::temp_directory_path() /
           ("hemicontact_writers_" + name + "_" + std::to_string(static_cast<long>(::getpid())));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string operator/(const std::string& f) const { return (path / f).string(); }
};

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// Model and a hand-made Solution whose Γ3 nodes cycle through separated / compliance / contact
/// and stick / slip+ / slip-, plus a fake history, so every writer field has a known source.
struct Fixture {
  json scene;
  Model md;
  SolveOptions opt;
  Solution sol;

  explicit Fixture(int n = 4) : scene(test_scene(n)), md(build_model(scene, ".")) {
    opt = solve_options_from_scene(scene);
    Vec x = Vec::Zero(md.dofs.n_free());
    for (Index i = 0; i < md.dofs.n_interior(); ++i) x[i] = 1e-3 * std::sin(0.7 * i + 0.3);
    const double g = 0.15;
    const double u_nu[] = {-0.01, 0.05, g};
    const double u_tau[] = {0.0, 0.01, -0.01};
    for (Index k = 0; k < md.contact.size(); ++k) {
      x[md.dofs.contact_dof(k, 0)] = u_nu[k % 3];
      x[md.dofs.contact_dof(k, 1)] = u_tau[(k / 3 + k) % 3];
    }
    sol.u = md.dofs.to_full(x);
    sol.x = md.dofs.to_reduced(sol.u);
    evaluate_solution(md, opt, sol);
    sol.backend = "ipopt";
    sol.backend_use = {"ipopt", true, ""};
    sol.message = "hand-made solution";
    sol.skipped = {"continuation: nothing to smooth"};
    sol.x_scale = 0.25;
    sol.f_scale = 8e-3;
    sol.timings = {{"backend", 0.5}, {"solve_total", 0.75}};
    for (int k = 0; k < 2; ++k) {
      OuterIteration h;
      h.k = k;
      h.stage = k;
      h.eps_tau = 1e-3 / (k + 1);
      h.eps_nu = 2e-3 / (k + 1);
      h.change_u = 0.5 / (k + 1);
      h.change_lambda = 0.25 / (k + 1);
      h.grad_norm = 1e-9 * (k + 1);
      h.backend.status = k ? SolveStatus::CONVERGED : SolveStatus::ACCEPTABLE;
      h.backend.iterations = 10 + k;
      h.backend.evaluations = 20 + k;
      h.backend.seconds = 0.125 * (k + 1);
      h.backend.message = "msg " + std::to_string(k);
      h.solver = "ipopt";  // the backend's own minimizations (an exact solver's would not count)
      sol.history.push_back(h);
    }
  }
};

// ------------------------------------------------------------------------------------ VTU

/// One <DataArray> of a VTU: its attributes and its numbers.
struct VtuArray {
  std::string type;
  int comps = 1;
  std::vector<double> values;
};

/// The values of an appended (binary) array at @p offset of the appended block: VTK's layout for
/// header_type UInt64, zlib blocks when @p compressed (vtk_writer.cpp), decoded independently here.
std::vector<double> appended_values(const std::string& block, size_t offset, const std::string& type, bool compressed) {
  const auto u64 = [&](size_t at) {
    std::uint64_t v;
    std::memcpy(&v, block.data() + at, 8);
    return v;
  };
  std::string raw;
  if (compressed) {
#if HEMICONTACT_HAS_ZLIB
    const std::uint64_t nblocks = u64(offset), bs = u64(offset + 8), last = u64(offset + 16);
    size_t at = offset + 24 + 8 * nblocks;
    for (std::uint64_t k = 0; k < nblocks; ++k) {
      const std::uint64_t csize = u64(offset + 24 + 8 * k);
      uLongf len = static_cast<uLongf>((k + 1 == nblocks && last) ? last : bs);
      std::string out(len, '\0');
      EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(out.data()), &len,
                           reinterpret_cast<const Bytef*>(block.data() + at), static_cast<uLong>(csize)),
                Z_OK);
      raw += out.substr(0, len);
      at += csize;
    }
#else
    ADD_FAILURE() << "a compressed VTU from a build without zlib";
#endif
  } else {
    raw = block.substr(offset + 8, u64(offset));
  }
  std::vector<double> v;
  const auto read = [&](auto tag) {
    using T = decltype(tag);
    for (size_t k = 0; k + sizeof(T) <= raw.size(); k += sizeof(T)) {
      T x;
      std::memcpy(&x, raw.data() + k, sizeof(T));
      v.push_back(static_cast<double>(x));
    }
  };
  if (type == "Float64")
    read(double());
  else if (type == "Int64")
    read(std::int64_t());
  else if (type == "Int32")
    read(std::int32_t());
  else
    read(std::uint8_t());
  return v;
}

/// Parse every named DataArray of a VTU, ASCII or appended binary (a minimal reader: enough for
/// our own output).
std::map<std::string, VtuArray> parse_vtu_arrays(const std::string& text) {
  std::map<std::string, VtuArray> out;
  const auto attr = [](const std::string& tag, const std::string& name) -> std::string {
    const auto p = tag.find(" " + name + "=\"");
    if (p == std::string::npos) return "";
    const auto b = p + name.size() + 3;
    return tag.substr(b, tag.find('"', b) - b);
  };
  // The XML ends where the appended block starts (its bytes may contain anything).
  const size_t appended_at = text.find("<AppendedData encoding=\"raw\">");
  const std::string xml = text.substr(0, appended_at);
  std::string block;
  if (appended_at != std::string::npos) block = text.substr(text.find('_', appended_at) + 1);
  const bool compressed = xml.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos;
  size_t pos = 0;
  while ((pos = xml.find("<DataArray", pos)) != std::string::npos) {
    const size_t tag_end = xml.find('>', pos);
    const std::string tag = xml.substr(pos, tag_end - pos);
    VtuArray a;
    a.type = attr(tag, "type");
    const std::string nc = attr(tag, "NumberOfComponents");
    a.comps = nc.empty() ? 1 : std::stoi(nc);
    if (attr(tag, "format") == "appended") {
      a.values = appended_values(block, std::stoul(attr(tag, "offset")), a.type, compressed);
      pos = tag_end;
    } else {
      EXPECT_EQ(attr(tag, "format"), "ascii");
      const size_t close = xml.find("</DataArray>", tag_end);
      EXPECT_NE(close, std::string::npos);
      std::istringstream body(xml.substr(tag_end + 1, close - tag_end - 1));
      std::string tok;
      while (body >> tok) a.values.push_back(std::strtod(tok.c_str(), nullptr));
      pos = close;
    }
    out[attr(tag, "Name")] = std::move(a);
  }
  return out;
}

std::string attribute_value(const std::string& text, const std::string& name) {
  const auto p = text.find(name + "=\"");
  if (p == std::string::npos) return "";
  const auto b = p + name.size() + 2;
  return text.substr(b, text.find('"', b) - b);
}

size_t count_of(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t p = text.find(part); p != std::string::npos; p = text.find(part, p + 1)) ++n;
  return n;
}

// The binary file (the default) carries exactly the ASCII file's numbers (ASCII writes each double
// in its shortest round-trip form, so both decode to the same bits), in fewer bytes; the statuses
// are also fields by name, and the codes' legend is in the file.
TEST(VtkWriter, BinaryEqualsAsciiAndStatusesHaveNames) {
  Fixture fx;
  TempDir dir("vtu_binary");
  write_vtu(dir / "a.vtu", fx.md, fx.sol, VtuFormat::ASCII);
  write_vtu(dir / "b.vtu", fx.md, fx.sol);
  const std::string ascii = read_text(dir / "a.vtu"), binary = read_text(dir / "b.vtu");
  EXPECT_CONTAINS(binary, "<AppendedData encoding=\"raw\">");
  EXPECT_EQ(binary.find("format=\"ascii\""), std::string::npos);
  if (HEMICONTACT_HAS_ZLIB) {
    EXPECT_CONTAINS(binary, "compressor=\"vtkZLibDataCompressor\"");
  }
  EXPECT_LT(binary.size(), ascii.size());
  const auto A = parse_vtu_arrays(ascii), B = parse_vtu_arrays(binary);
  ASSERT_EQ(A.size(), B.size());
  for (const auto& [name, a] : A) {
    ASSERT_TRUE(B.count(name)) << name;
    EXPECT_EQ(B.at(name).type, a.type) << name;
    EXPECT_EQ(B.at(name).comps, a.comps) << name;
    EXPECT_EQ(B.at(name).values, a.values) << name;  // bit for bit
  }
  // One 0/1 field per 2D status, agreeing with the codes on every node.
  const auto& sn = B.at("status_normal").values;
  const auto& st = B.at("status_tangential").values;
  const std::vector<std::pair<std::string, std::pair<const std::vector<double>*, int>>> fields = {
      {"separated", {&sn, 0}}, {"compliance", {&sn, 1}}, {"contact", {&sn, 2}},
      {"stick", {&st, 0}},     {"slip_plus", {&st, 1}},  {"slip_minus", {&st, 2}}};
  for (const auto& [name, code] : fields) {
    ASSERT_TRUE(B.count(name)) << name;
    const auto& v = B.at(name).values;
    for (size_t a = 0; a < v.size(); ++a) EXPECT_EQ(v[a], (*code.first)[a] == code.second ? 1.0 : 0.0) << name << a;
  }
  EXPECT_FALSE(B.count("slip"));  // 3D only
  std::string legend;
  for (double c : B.at("status_legend").values) legend += static_cast<char>(c);
  EXPECT_CONTAINS(legend, "status_normal: -1 not on Gamma3, 0 separated, 1 compliance, 2 contact");
  EXPECT_CONTAINS(legend, "0 stick, 1 slip+, 2 slip-, 3 slip");
}

TEST(VtkWriter, ArraysCountsAndValuesRoundTrip) {
  Fixture fx;
  const Model& md = fx.md;
  const Solution& sol = fx.sol;
  TempDir dir("vtu");
  write_vtu(dir / "solution.vtu", md, sol, VtuFormat::ASCII);
  const std::string text = read_text(dir / "solution.vtu");

  // Well-formed enough: the header, one root, balanced tags.
  EXPECT_EQ(text.rfind("<?xml version=\"1.0\"?>", 0), 0u);
  EXPECT_CONTAINS(text, "<VTKFile type=\"UnstructuredGrid\"");
  EXPECT_EQ(text.substr(text.size() - 11), "</VTKFile>\n");
  EXPECT_EQ(count_of(text, "<DataArray"), count_of(text, "</DataArray>"));
  for (const char* t : {"UnstructuredGrid", "Piece", "PointData", "CellData", "Points", "Cells"})
    EXPECT_EQ(count_of(text, std::string("<") + t + " ") + count_of(text, std::string("<") + t + ">"),
              count_of(text, std::string("</") + t + ">"))
        << t;

  const Index N = md.mesh.num_nodes(), M = md.mesh.num_cells(), nc = md.contact.size();
  ASSERT_EQ(N, 25);
  ASSERT_EQ(M, 32);
  ASSERT_EQ(nc, 5);
  EXPECT_EQ(attribute_value(text, "NumberOfPoints"), std::to_string(N));
  EXPECT_EQ(attribute_value(text, "NumberOfCells"), std::to_string(M));

  const auto arrays = parse_vtu_arrays(text);
  const std::map<std::string, std::pair<Index, int>> expected = {{"displacement", {N, 3}},
                                                                 {"gamma3", {N, 1}},
                                                                 {"u_nu", {N, 1}},
                                                                 {"u_tau", {N, 1}},
                                                                 {"sigma_nu", {N, 1}},
                                                                 {"sigma_tau", {N, 1}},
                                                                 {"xi", {N, 1}},
                                                                 {"lambda", {N, 1}},
                                                                 {"u_tau_vec", {N, 3}},
                                                                 {"sigma_tau_vec", {N, 3}},
                                                                 {"status_normal", {N, 1}},
                                                                 {"status_tangential", {N, 1}},
                                                                 {"strain", {M, 3}},
                                                                 {"stress", {M, 3}},
                                                                 {"von_mises", {M, 1}},
                                                                 {"Points", {N, 3}},
                                                                 {"connectivity", {3 * M, 1}},
                                                                 {"offsets", {M, 1}},
                                                                 {"types", {M, 1}}};
  for (const auto& [name, rc] : expected) {
    ASSERT_TRUE(arrays.count(name)) << "missing array " << name;
    EXPECT_EQ(arrays.at(name).comps, rc.second) << name;
    EXPECT_EQ(static_cast<Index>(arrays.at(name).values.size()), rc.first * rc.second) << name;
  }
  EXPECT_EQ(arrays.at("status_normal").type, "Int32");
  EXPECT_EQ(arrays.at("status_tangential").type, "Int32");
  EXPECT_EQ(arrays.at("displacement").type, "Float64");

  // Full precision: the numbers read back are the doubles that were written.
  const auto& disp = arrays.at("displacement").values;
  const auto& pts = arrays.at("Points").values;
  for (Index a = 0; a < N; ++a) {
    for (int c = 0; c < 2; ++c) {
      const double u = sol.u[2 * a + c];
      EXPECT_LE(std::abs(disp[3 * a + c] - u), 1e-15 * std::abs(u)) << "node " << a;
      EXPECT_EQ(pts[3 * a + c], md.mesh.points(a, c));
    }
    EXPECT_EQ(disp[3 * a + 2], 0.0);
    EXPECT_EQ(pts[3 * a + 2], 0.0);
  }

  // Γ3 fields on Γ3 nodes, mask and −1 status elsewhere.
  std::vector<Index> k_of(N, -1);
  for (Index k = 0; k < nc; ++k) k_of[md.contact.node[k]] = k;
  const ContactState& s = sol.state;
  for (Index a = 0; a < N; ++a) {
    const Index k = k_of[a];
    EXPECT_EQ(arrays.at("gamma3").values[a], k >= 0 ? 1.0 : 0.0);
    if (k < 0) {
      EXPECT_EQ(arrays.at("status_normal").values[a], -1.0);
      EXPECT_EQ(arrays.at("status_tangential").values[a], -1.0);
      EXPECT_EQ(arrays.at("u_nu").values[a], 0.0);
      continue;
    }
    EXPECT_EQ(arrays.at("u_nu").values[a], s.u_nu[k]);
    EXPECT_EQ(arrays.at("u_tau").values[a], s.u_tau[k]);
    EXPECT_EQ(arrays.at("sigma_nu").values[a], s.sigma_nu[k]);
    EXPECT_EQ(arrays.at("sigma_tau").values[a], s.sigma_tau[k]);
    EXPECT_EQ(arrays.at("xi").values[a], s.xi[k]);
    EXPECT_EQ(arrays.at("lambda").values[a], s.lambda[k]);
    EXPECT_EQ(arrays.at("status_normal").values[a], status_code(sol.status[k].normal));
    EXPECT_EQ(arrays.at("status_tangential").values[a], status_code(sol.status[k].tangential));
  }
  // The hand-made field really exercises every normal status.
  EXPECT_EQ(sol.status[0].normal, NormalStatus::SEPARATED);
  EXPECT_EQ(sol.status[1].normal, NormalStatus::COMPLIANCE);
  EXPECT_EQ(sol.status[2].normal, NormalStatus::CONTACT);

  // Cells: triangles, connectivity and offsets; strain/stress/von Mises per cell.
  const RowMat strain = cell_strains(md.mesh, sol.u);
  for (Index c = 0; c < M; ++c) {
    EXPECT_EQ(arrays.at("types").values[c], 5.0);
    EXPECT_EQ(arrays.at("offsets").values[c], 3.0 * (c + 1));
    for (int a = 0; a < 3; ++a) EXPECT_EQ(arrays.at("connectivity").values[3 * c + a], md.mesh.cells(c, a));
    const Vec sig = md.material->stress(strain.row(c).transpose());
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(arrays.at("strain").values[3 * c + i], strain(c, i));
      EXPECT_EQ(arrays.at("stress").values[3 * c + i], sig[i]);
    }
    EXPECT_EQ(arrays.at("von_mises").values[c], von_mises(sig.transpose(), 2));
  }
}

TEST(VtkWriter, RefusesMismatchedSolutionAndUnwritablePath) {
  Fixture fx;
  Solution bad = fx.sol;
  bad.status.clear();
  try {
    write_vtu("never_written.vtu", fx.md, bad);
    ADD_FAILURE() << "expected an internal error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INTERNAL);
  }
  EXPECT_FALSE(fs::exists("never_written.vtu"));
  try {
    write_vtu("/nonexistent_dir_hemicontact/x.vtu", fx.md, fx.sol);
    ADD_FAILURE() << "expected an output error";
  } catch (const Error& e) {
    // A write that fails is an output failure (exit 6), named with its file and reason.
    EXPECT_EQ(e.code(), EXIT_OUTPUT);
    EXPECT_CONTAINS(e.what(), "cannot write '/nonexistent_dir_hemicontact/x.vtu': No such file or directory");
  }
}

#if HEMICONTACT_HAS_GMSH
TEST(VtkWriter, TetrahedraIn3D) {
  json scene = json::parse(R"({
    "mesh": {"type": "gmsh"}, "material": {"E": 2000, "nu": 0.3},
    "boundary": {"gamma1": [{"physical": "bottom"}]}, "loads": {"body_force": [0, 0, -1e-3]}})");
  scene["mesh"]["file"] = std::string(HEMICONTACT_SOURCE_DIR) + "/tests/data/unit_cube_6tets.msh";
  scene = validate_scene(scene);
  const Model md = build_model(scene, ".");
  ASSERT_EQ(md.dim(), 3);
  Solution sol;
  sol.u = md.dofs.to_full(Vec::LinSpaced(md.dofs.n_free(), 1e-4, 3e-4));
  sol.x = md.dofs.to_reduced(sol.u);
  evaluate_solution(md, solve_options_from_scene(scene), sol);
  TempDir dir("vtu3d");
  write_vtu(dir / "s.vtu", md, sol);
  const auto arrays = parse_vtu_arrays(read_text(dir / "s.vtu"));
  const Index N = md.mesh.num_nodes(), M = md.mesh.num_cells();
  ASSERT_EQ(arrays.at("types").values.size(), static_cast<size_t>(M));
  for (double t : arrays.at("types").values) EXPECT_EQ(t, 10.0);
  EXPECT_EQ(arrays.at("connectivity").values.size(), static_cast<size_t>(4 * M));
  EXPECT_EQ(arrays.at("strain").comps, 6);
  EXPECT_EQ(arrays.at("stress").values.size(), static_cast<size_t>(6 * M));
  const auto& disp = arrays.at("displacement").values;
  ASSERT_EQ(disp.size(), static_cast<size_t>(3 * N));
  for (Index i = 0; i < 3 * N; ++i) EXPECT_EQ(disp[i], sol.u[i]);
}
#endif

// ------------------------------------------------------------------------------------ CSV

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream in(s);
  while (std::getline(in, cur, sep)) out.push_back(cur);
  return out;
}

TEST(CsvWriter, OneRowPerGamma3Node) {
  Fixture fx;
  const Model& md = fx.md;
  const Solution& sol = fx.sol;
  TempDir dir("csv");
  write_gamma3_csv(dir / "gamma3.csv", md, sol);
  const auto lines = split(read_text(dir / "gamma3.csv"), '\n');
  ASSERT_EQ(static_cast<Index>(lines.size()), md.contact.size() + 1);
  EXPECT_EQ(lines[0], "index,node,x,y,w,g,u_nu,u_tau,sigma_nu,sigma_tau,xi,lambda,status");
  const ContactState& s = sol.state;
  for (Index k = 0; k < md.contact.size(); ++k) {
    const auto f = split(lines[k + 1], ',');
    ASSERT_EQ(f.size(), 13u) << lines[k + 1];
    EXPECT_EQ(std::stol(f[0]), k);
    EXPECT_EQ(std::stoi(f[1]), md.contact.node[k]);
    const double expect[] = {md.mesh.points(md.contact.node[k], 0),
                             md.mesh.points(md.contact.node[k], 1),
                             md.contact.w[k],
                             md.contact.g[k],
                             s.u_nu[k],
                             s.u_tau[k],
                             s.sigma_nu[k],
                             s.sigma_tau[k],
                             s.xi[k],
                             s.lambda[k]};
    for (int i = 0; i < 10; ++i) EXPECT_EQ(std::strtod(f[2 + i].c_str(), nullptr), expect[i]) << "column " << 2 + i;
    EXPECT_EQ(f[12], sol.status[k].str());
  }
  EXPECT_EQ(split(lines[1], ',')[12], "separated/stick");
}

// ------------------------------------------------------------------------------------ report

TEST(Report, EveryKeyWithTheSolutionsValues) {
  Fixture fx;
  const Model& md = fx.md;
  const Solution& sol = fx.sol;
  const json r = make_report(md, sol, fx.opt);
  for (const char* key : {"scene",         "version",  "mesh",          "dofs",    "material",    "laws",
                          "backend",       "energy",   "energy_norm",   "a_uu",    "f_u",         "j_term",
                          "friction_term", "max_u_nu", "status_counts", "nodes",   "certificate", "fixed_point",
                          "skipped",       "scales",   "timings",       "message", "ok"})
    EXPECT_TRUE(r.contains(key)) << key;

  EXPECT_EQ(r["scene"], fx.scene);
  EXPECT_EQ(r["version"], HEMICONTACT_VERSION);
  EXPECT_EQ(r["mesh"]["origin"], md.mesh.origin);
  EXPECT_EQ(r["mesh"]["dim"], 2);
  EXPECT_EQ(r["mesh"]["nodes"], 25);
  EXPECT_EQ(r["mesh"]["cells"], 32);
  EXPECT_EQ(r["mesh"]["gamma3_nodes"], 5);
  EXPECT_EQ(r["mesh"]["h"].get<double>(), md.mesh.max_edge_length());
  EXPECT_EQ(r["dofs"], md.dofs.n_free());
  EXPECT_EQ(r["material"]["description"], md.material->describe());
  EXPECT_EQ(r["material"]["m_F"].get<double>(), md.material->m_F());
  EXPECT_EQ(r["material"]["L_F"].get<double>(), md.material->L_F());
  ASSERT_TRUE(md.normal_law && md.friction);
  EXPECT_EQ(r["laws"]["normal_law"], md.normal_law->describe());
  EXPECT_EQ(r["laws"]["friction"], md.friction->describe());
  EXPECT_EQ(r["laws"]["gap"], md.gap.describe());
  EXPECT_EQ(r["backend"]["name"], "ipopt");
  EXPECT_EQ(r["backend"]["iterations"], 21);
  EXPECT_EQ(r["backend"]["evaluations"], 41);
  EXPECT_EQ(r["backend"]["seconds"].get<double>(), 0.375);
  EXPECT_EQ(r["energy"].get<double>(), sol.energy);
  EXPECT_EQ(r["energy_norm"].get<double>(), sol.energy_norm);
  EXPECT_EQ(r["a_uu"].get<double>(), sol.a_uu);
  EXPECT_EQ(r["f_u"].get<double>(), sol.f_u);
  EXPECT_EQ(r["j_term"].get<double>(), sol.j_term);
  EXPECT_EQ(r["friction_term"].get<double>(), sol.friction_term);
  EXPECT_EQ(r["max_u_nu"].get<double>(), sol.max_u_nu);
  for (const auto& [k, v] : sol.status_counts()) EXPECT_EQ(r["status_counts"][k], v) << k;

  ASSERT_EQ(r["nodes"].size(), 5u);
  for (Index k = 0; k < 5; ++k) {
    const json& n = r["nodes"][k];
    EXPECT_EQ(n["x"].get<double>(), md.mesh.points(md.contact.node[k], 0));
    EXPECT_EQ(n["y"].get<double>(), md.mesh.points(md.contact.node[k], 1));
    EXPECT_FALSE(n.contains("z"));
    EXPECT_EQ(n["u_nu"].get<double>(), sol.state.u_nu[k]);
    EXPECT_EQ(n["u_tau"].get<double>(), sol.state.u_tau[k]);
    EXPECT_EQ(n["sigma_nu"].get<double>(), sol.state.sigma_nu[k]);
    EXPECT_EQ(n["sigma_tau"].get<double>(), sol.state.sigma_tau[k]);
    EXPECT_EQ(n["xi"].get<double>(), sol.state.xi[k]);
    EXPECT_EQ(n["lambda"].get<double>(), sol.state.lambda[k]);
    EXPECT_EQ(n["status"], sol.status[k].str());
  }

  const CertificateReport& c = sol.certificate;
  EXPECT_EQ(r["certificate"]["passed"], c.passed);
  EXPECT_EQ(r["certificate"]["tol"].get<double>(), c.tol);
  EXPECT_EQ(r["certificate"]["max_residual"].get<double>(), c.max_residual);
  EXPECT_EQ(r["certificate"]["length_scale"].get<double>(), c.length_scale);
  EXPECT_EQ(r["certificate"]["force_scale"].get<double>(), c.force_scale);
  EXPECT_EQ(r["certificate"]["traction_scale"].get<double>(), c.traction_scale);
  ASSERT_FALSE(c.residuals.empty());
  for (const auto& e : c.residuals) {
    EXPECT_EQ(r["certificate"]["residuals"][e.name]["value"].get<double>(), e.value) << e.name;
    EXPECT_EQ(r["certificate"]["residuals"][e.name]["worst"], e.worst) << e.name;
  }

  const json& fp = r["fixed_point"];
  EXPECT_EQ(fp["converged"], sol.fixed_point_converged);
  EXPECT_EQ(fp["iterations"], 2);
  ASSERT_EQ(fp["history"].size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const json& h = fp["history"][k];
    const OuterIteration& o = sol.history[k];
    EXPECT_EQ(h["k"], o.k);
    EXPECT_EQ(h["stage"], o.stage);
    EXPECT_EQ(h["eps_tau"].get<double>(), o.eps_tau);
    EXPECT_EQ(h["eps_nu"].get<double>(), o.eps_nu);
    EXPECT_EQ(h["change_u"].get<double>(), o.change_u);
    EXPECT_EQ(h["change_lambda"].get<double>(), o.change_lambda);
    EXPECT_EQ(h["grad_norm"].get<double>(), o.grad_norm);
    EXPECT_EQ(h["backend_status"], to_string(o.backend.status));
    EXPECT_EQ(h["backend_iterations"], o.backend.iterations);
    EXPECT_EQ(h["backend_evaluations"], o.backend.evaluations);
    EXPECT_EQ(h["backend_seconds"].get<double>(), o.backend.seconds);
    EXPECT_EQ(h["backend_message"], o.backend.message);
  }
  EXPECT_EQ(fp["history"][0]["backend_status"], "acceptable");

  EXPECT_EQ(r["skipped"], json::array({"continuation: nothing to smooth"}));
  EXPECT_EQ(r["scales"]["x_scale"].get<double>(), 0.25);
  EXPECT_EQ(r["scales"]["f_scale"].get<double>(), 8e-3);
  for (const auto& [k, v] : md.timings) EXPECT_TRUE(r["timings"].contains(k)) << k;
  EXPECT_EQ(r["timings"]["solve_total"].get<double>(), 0.75);
  EXPECT_EQ(r["message"], "hand-made solution");
  EXPECT_EQ(r["ok"], sol.backend_ok && sol.fixed_point_converged && c.passed);
  EXPECT_EQ(r["options"]["certificate_tol"].get<double>(), fx.opt.certificate_tol);
}

// "The certificate decides success, not the backend's own word": ok needs the fixed point and the
// certificate; a backend failure with a certified answer is still ok.
// read_solve_records is solve_records read back (a solve by another process, the petsc engine
// streamed: studies/petsc_process.hpp): every record it reads equals the written one, a NaN
// (written as null) comes back NaN, and what the answer is worth is not read (it is judged anew).
TEST(Report, SolveRecordsReadBackAsWritten) {
  Fixture F;
  F.sol.fixed_point_converged = false;
  F.sol.history[1].contraction = 0.5;
  F.sol.polish = {true, true, 3, 1e-6, 1e-13, "accepted"};
  F.sol.formulation = "full";
  const json written = json::parse(solve_records(F.sol, F.opt, true).dump());
  Solution back;
  read_solve_records(written, back);
  EXPECT_EQ(back.backend, F.sol.backend);
  EXPECT_EQ(back.backend_use.requested, F.sol.backend_use.requested);
  EXPECT_EQ(back.backend_use.ran, F.sol.backend_use.ran);
  EXPECT_FALSE(back.fixed_point_converged);
  EXPECT_EQ(back.skipped, F.sol.skipped);
  EXPECT_EQ(back.formulation, "full");
  EXPECT_EQ(back.x_scale, F.sol.x_scale);
  EXPECT_EQ(back.f_scale, F.sol.f_scale);
  EXPECT_EQ(back.message, F.sol.message);
  EXPECT_TRUE(back.polish.accepted);
  EXPECT_EQ(back.polish.iterations, 3);
  EXPECT_EQ(back.polish.after, 1e-13);
  ASSERT_EQ(back.history.size(), F.sol.history.size());
  for (size_t k = 0; k < back.history.size(); ++k) {
    const OuterIteration &a = back.history[k], &b = F.sol.history[k];
    EXPECT_EQ(a.stage, b.stage);
    EXPECT_EQ(a.eps_tau, b.eps_tau);
    EXPECT_EQ(a.grad_norm, b.grad_norm);
    EXPECT_EQ(a.backend.status, b.backend.status);
    EXPECT_EQ(a.backend.iterations, b.backend.iterations);
    EXPECT_EQ(a.backend.message, b.backend.message);
    EXPECT_EQ(a.solver, b.solver);
  }
  EXPECT_TRUE(std::isnan(back.history[0].contraction));
  EXPECT_EQ(back.history[1].contraction, 0.5);
  EXPECT_EQ(back.solved_by(), F.sol.solved_by());
  EXPECT_EQ(json::parse(solve_records(back, F.opt, true).dump()).at("backend"), written.at("backend"));
  EXPECT_FALSE(back.certificate.passed);  // not read: the reader's own judge decides
}

TEST(Report, OkNeedsFixedPointAndCertificateNotTheBackendsWord) {
  Fixture fx;
  fx.sol.certificate.passed = true;
  EXPECT_TRUE(make_report(fx.md, fx.sol, fx.opt)["ok"].get<bool>());
  fx.sol.fixed_point_converged = false;
  EXPECT_FALSE(make_report(fx.md, fx.sol, fx.opt)["ok"].get<bool>());
  fx.sol.fixed_point_converged = true;
  fx.sol.backend_ok = false;
  EXPECT_TRUE(make_report(fx.md, fx.sol, fx.opt)["ok"].get<bool>());
  fx.sol.backend_ok = true;
  fx.sol.certificate.passed = false;
  EXPECT_FALSE(make_report(fx.md, fx.sol, fx.opt)["ok"].get<bool>());
}

TEST(Report, WrittenFileIsValidJsonEvenWithNonFiniteNumbers) {
  Fixture fx;
  fx.sol.history[0].change_lambda = std::numeric_limits<double>::quiet_NaN();
  fx.sol.history[1].eps_tau = INF;
  fx.sol.certificate.max_residual = -INF;
  const json r = make_report(fx.md, fx.sol, fx.opt);
  TempDir dir("json");
  write_report(dir / "report.json", r);
  const std::string text = read_text(dir / "report.json");
  EXPECT_EQ(text.back(), '\n');
  EXPECT_CONTAINS(text, "{\n  \"");     // 2-space indent
  const json back = json::parse(text);  // throws on invalid JSON
  EXPECT_TRUE(back["fixed_point"]["history"][0]["change_lambda"].is_null());
  EXPECT_TRUE(back["fixed_point"]["history"][1]["eps_tau"].is_null());
  EXPECT_TRUE(back["certificate"]["max_residual"].is_null());
  // Every finite double survives the round trip exactly.
  EXPECT_EQ(back["energy"].get<double>(), fx.sol.energy);
  EXPECT_EQ(back["nodes"][3]["sigma_nu"].get<double>(), fx.sol.state.sigma_nu[3]);
  EXPECT_EQ(back["scene"], fx.scene);
}

// ------------------------------------------------------------------------------------ summary

TEST(Summary, CountsPerNodeStatusesAndCertificate) {
  Fixture fx;
  const std::string s = summary_table(fx.md, fx.sol);
  EXPECT_CONTAINS(s, "25 nodes, 32 cells, 5 gamma3 nodes");
  EXPECT_CONTAINS(s, "separated");
  EXPECT_CONTAINS(s, "compliance");
  EXPECT_CONTAINS(s, "slip-");
  // The counts row lists each count under its name.
  const auto counts = fx.sol.status_counts();
  std::string expect_row;
  for (const char* n : {"separated", "compliance", "contact"}) expect_row += std::to_string(counts.at(n));
  expect_row += "|";
  for (const char* n : {"stick", "slip+", "slip-"}) expect_row += std::to_string(counts.at(n));
  bool found = false;
  for (const auto& line : split(s, '\n')) {
    std::string compact;
    for (char ch : line)
      if (ch != ' ') compact += ch;
    found = found || compact == expect_row;
  }
  EXPECT_TRUE(found) << "no counts row " << expect_row << " in\n" << s;
  for (const auto& st : fx.sol.status) EXPECT_CONTAINS(s, st.str());
  EXPECT_CONTAINS(s, fx.sol.certificate.passed ? "passed" : "FAILED");
  EXPECT_CONTAINS(s, "ipopt: 2 minimizations (eps-stage 0..1), 21 iterations, 41 evaluations");
  EXPECT_CONTAINS(s, "solve_total");
}

TEST(Summary, RunLengthBeyond33Nodes) {
  Fixture fx(40);
  ASSERT_GT(fx.md.contact.size(), 33);
  const std::string runs = status_runs(fx.sol);
  const std::string s = summary_table(fx.md, fx.sol);
  EXPECT_CONTAINS(s, runs);
  EXPECT_CONTAINS(runs, " x1");
  // The runs add up to the number of Γ3 nodes.
  int total = 0;
  for (const auto& part : split(runs, ',')) total += std::stoi(part.substr(part.rfind('x') + 1));
  EXPECT_EQ(total, fx.md.contact.size());

  Solution sol;
  NodeStatus a{NormalStatus::COMPLIANCE, TangentialStatus::SLIP_MINUS};
  NodeStatus b{NormalStatus::CONTACT, TangentialStatus::SLIP_MINUS};
  NodeStatus c{NormalStatus::CONTACT, TangentialStatus::STICK};
  sol.status = {a, a, b, b, b, c};
  EXPECT_EQ(status_runs(sol), "compliance/slip- x2, contact/slip- x3, contact/stick x1");
  EXPECT_EQ(status_runs(Solution{}), "");
}

// ------------------------------------------------------------------------------------ --out

std::string input_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "expected an input error";
  return "";
}

TEST(OutputDir, CreatesRefusesFilesAndKeepsResults) {
  TempDir dir("out");
  const std::string nested = dir / "a/b/c";
  prepare_output_dir(nested, false);
  EXPECT_TRUE(fs::is_directory(nested));
  // the manifest and the lock only
  EXPECT_EQ(std::distance(fs::directory_iterator(nested), fs::directory_iterator()), 2);
  EXPECT_TRUE(fs::exists(nested + "/" + OUTPUT_MANIFEST));
  EXPECT_TRUE(fs::exists(nested + "/" + OUTPUT_LOCK));
  EXPECT_TRUE(output_files(nested).empty());
  prepare_output_dir(nested, false);  // an existing directory without results is fine

  const std::string file = dir / "plain.txt";
  std::ofstream(file) << "user data\n";
  EXPECT_EQ(input_error_of([&] { prepare_output_dir(file, true); }),
            "--out '" + file + "': exists and is not a directory");
  EXPECT_CONTAINS(input_error_of([&] { prepare_output_dir(file + "/sub", false); }), "--out '" + file + "/sub'");
  EXPECT_EQ(read_text(file), "user data\n");

  // A report.json the manifest does not list is not ours: refused as a name the run would write,
  // kept with --force (it once counted as proof that the tool wrote the folder, and --force then
  // removed the user's files).
  std::ofstream(nested + "/report.json") << "{}\n";
  EXPECT_EQ(input_error_of([&] { prepare_output_dir(nested, true, {"report.json"}); }),
            "--out '" + nested + "': 'report.json' exists and was not written by hemicontact (it is not listed in " +
                OUTPUT_MANIFEST + "); move it away or choose another --out");
  prepare_output_dir(nested, true);
  EXPECT_EQ(read_text(nested + "/report.json"), "{}\n");
  fs::remove(nested + "/report.json");
  write_text_file(nested + "/report.json", "{}\n");  // now one of ours
  EXPECT_EQ(input_error_of([&] { prepare_output_dir(nested, false); }),
            "--out '" + nested + "' already holds results (report.json); pass --force to replace them");
  EXPECT_EQ(read_text(nested + "/report.json"), "{}\n");
  prepare_output_dir(nested, true);
  EXPECT_FALSE(fs::exists(nested + "/report.json"));  // --force: the previous result set goes
}

// The manifest: every file written through write_text_file is listed once; --force removes exactly
// those (and report.json), never a user's file, never a name that leaves the folder; a user's file
// with the name of one the run will write is refused even with --force.
TEST(OutputDir, ForceReplacesExactlyTheFilesOfTheEarlierRun) {
  TempDir dir("manifest");
  const std::string out = dir / "res";
  prepare_output_dir(out, false);
  write_text_file(out + "/solution.vtu", "old vtu\n");
  write_text_file(out + "/gamma3.csv", "old csv\n");
  write_text_file(out + "/gamma3.csv", "old csv again\n");  // listed once
  EXPECT_EQ(output_files(out), (std::vector<std::string>{"solution.vtu", "gamma3.csv"}));
  std::ofstream(out + "/notes.txt") << "mine\n";
  std::ofstream(dir / "outside.txt") << "mine too\n";
  // A manifest edited to point outside the folder, or at a subfolder, is not followed.
  std::ofstream(out + "/" + OUTPUT_MANIFEST, std::ios::app) << "../outside.txt\n.\n\nsub\n";
  fs::create_directories(out + "/sub");
  EXPECT_CONTAINS(input_error_of([&] { prepare_output_dir(out, false); }), "already holds results (solution.vtu");
  prepare_output_dir(out, true, {"report.json", "gamma3.csv"});
  EXPECT_FALSE(fs::exists(out + "/solution.vtu"));
  EXPECT_FALSE(fs::exists(out + "/gamma3.csv"));
  EXPECT_EQ(read_text(out + "/notes.txt"), "mine\n");
  EXPECT_EQ(read_text(dir / "outside.txt"), "mine too\n");
  EXPECT_TRUE(fs::is_directory(out + "/sub"));
  EXPECT_TRUE(output_files(out).empty());

  std::ofstream(out + "/gamma3.csv") << "the user's own\n";
  EXPECT_CONTAINS(input_error_of([&] { prepare_output_dir(out, true, {"gamma3.csv"}); }),
                  "'gamma3.csv' exists and was not written by hemicontact");
  EXPECT_EQ(read_text(out + "/gamma3.csv"), "the user's own\n");

  // A report.json without a manifest of ours proves nothing (a user's, or anyone's):
  // the names the run would write are refused, with --force too, and nothing is removed.
  const std::string old = dir / "old";
  fs::create_directories(old);
  for (const char* f : {"report.json", "solution.vtu", "gamma3.csv", "notes.txt"}) std::ofstream(old + "/" + f) << f;
  for (bool force : {false, true})
    EXPECT_CONTAINS(input_error_of([&] {
                      prepare_output_dir(old, force, {"report.json", "solution.vtu", "gamma3.csv"});
                    }),
                    "'report.json' exists and was not written by hemicontact");
  for (const char* f : {"report.json", "solution.vtu", "gamma3.csv", "notes.txt"}) EXPECT_EQ(read_text(old + "/" + f), f);
  // Nor does a manifest without the signature line (an older version's, or written by hand):
  // refused naming it, its files kept.
  std::ofstream(old + "/" + OUTPUT_MANIFEST) << "notes.txt\nsolution.vtu\n";
  EXPECT_CONTAINS(input_error_of([&] { prepare_output_dir(old, true); }),
                  std::string(OUTPUT_MANIFEST) + " is not a file list written by hemicontact (its first line is not '" +
                      OUTPUT_MANIFEST_SIGNATURE + "')");
  for (const char* f : {"report.json", "solution.vtu", "gamma3.csv", "notes.txt"}) EXPECT_EQ(read_text(old + "/" + f), f);
}

// The manifest parser: the signature first, then plain names only, each once; what it returns
// is what a manifest with those names reads back as.
TEST(OutputDir, ManifestParserKeepsPlainNamesAfterTheSignature) {
  const std::string sig = std::string(OUTPUT_MANIFEST_SIGNATURE) + "\n";
  EXPECT_FALSE(parse_manifest(""));
  EXPECT_FALSE(parse_manifest("report.json\n"));
  EXPECT_FALSE(parse_manifest(" " + sig));
  EXPECT_FALSE(parse_manifest(sig + std::string(MAX_MANIFEST_BYTES, 'a')));
  EXPECT_EQ(parse_manifest(sig), std::vector<std::string>{});
  EXPECT_EQ(parse_manifest(sig + "a.vtu\n../x\n/etc/passwd\n.\n..\n\nb\x01\nc\xe9\n" + OUTPUT_MANIFEST + "\n" +
                           OUTPUT_LOCK + "\nsub/x\na.vtu\n.a.vtu.partial\nlast"),
            (std::vector<std::string>{"a.vtu", ".a.vtu.partial", "last"}));
  EXPECT_TRUE(plain_output_name("level_16.vtu"));
  EXPECT_FALSE(plain_output_name(std::string("a\0b", 3)));
}

// Nothing in the folder is written, read or removed through a symbolic link, and
// a FIFO is refused rather than opened (it hung the run). Each name the run uses is named.
TEST(OutputDir, LinksAndFifosInTheFolderAreRefusedNotFollowed) {
  TempDir dir("links");
  const std::string out = dir / "res";
  const std::string victim = dir / "victim";
  std::ofstream(victim) << "the user's\n";
  fs::create_directories(out);
  struct Case {
    std::string planted, expect;
  };
  const std::vector<Case> cases{
      {".report.json.partial", "'.report.json.partial' is a symbolic link, not a file hemicontact wrote"},
      {"report.json", "'report.json' is a symbolic link, not a file hemicontact wrote"},
      {OUTPUT_LOCK, "the lock file '" + out + "/" + OUTPUT_LOCK + "' is a symbolic link, not a regular file"},
      {OUTPUT_MANIFEST, std::string(OUTPUT_MANIFEST) + " is not a file list written by hemicontact (it is a symbolic link)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.planted);
    fs::remove(out + "/" + OUTPUT_MANIFEST);
    fs::remove(out + "/" + c.planted);  // the lock file, left by the case before
    fs::create_symlink("../victim", out + "/" + c.planted);
    EXPECT_CONTAINS(input_error_of([&] { prepare_output_dir(out, true, {"report.json"}); }), c.expect);
    EXPECT_EQ(read_text(victim), "the user's\n");
    fs::remove(out + "/" + c.planted);
  }
  for (const std::string& planted : {std::string("report.json"), std::string(OUTPUT_MANIFEST), std::string(OUTPUT_LOCK)}) {
    SCOPED_TRACE(planted);
    fs::remove(out + "/" + OUTPUT_MANIFEST);
    fs::remove(out + "/" + planted);
    ASSERT_EQ(::mkfifo((out + "/" + planted).c_str(), 0600), 0);
    EXPECT_CONTAINS(input_error_of([&] { prepare_output_dir(out, false, {"report.json"}); }), "is a FIFO");
    fs::remove(out + "/" + planted);
  }
  // A link planted where a temporary goes after the check: created exclusively, never followed.
  prepare_output_dir(out, false, {"report.json"});
  fs::create_symlink("../victim", out + "/.gamma3.csv.partial");
  try {
    write_text_file(out + "/gamma3.csv", "x\n");
    ADD_FAILURE() << "wrote through a link";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_OUTPUT);
    EXPECT_CONTAINS(std::string(e.what()), "its temporary '.gamma3.csv.partial' exists already");
  }
  EXPECT_EQ(read_text(victim), "the user's\n");
  EXPECT_TRUE(fs::is_symlink(out + "/.gamma3.csv.partial"));  // not ours to remove
  // A link planted under the final name is replaced by the rename, its target untouched.
  fs::remove(out + "/.gamma3.csv.partial");
  fs::create_symlink("../victim", out + "/gamma3.csv");
  write_text_file(out + "/gamma3.csv", "x\n");
  EXPECT_FALSE(fs::is_symlink(out + "/gamma3.csv"));
  EXPECT_EQ(read_text(victim), "the user's\n");
  EXPECT_EQ(non_regular_kind(out + "/gamma3.csv"), "");
  fs::create_symlink("../victim", out + "/fig2.png");
  EXPECT_EQ(non_regular_kind(out + "/fig2.png"), "a symbolic link");
}

// Numbered names (level_<n>.vtu, solution_<k>.vtu) are checked before the run like fixed ones,
// their temporaries too.
TEST(OutputDir, NumberedNamesOfTheUserAreRefused) {
  TempDir dir("numbered");
  const std::string out = dir / "res";
  fs::create_directories(out);
  std::ofstream(out + "/solution_12.vtu") << "mine\n";
  std::ofstream(out + "/solution_x.vtu") << "not a number: not a name the run writes\n";
  EXPECT_CONTAINS(input_error_of([&] { prepare_output_dir(out, true, {}, {{"solution_", ".vtu"}}); }),
                  "'solution_12.vtu' exists and was not written by hemicontact");
  fs::remove(out + "/solution_12.vtu");
  std::ofstream(out + "/.solution_3.vtu.partial") << "mine\n";
  EXPECT_CONTAINS(input_error_of([&] { prepare_output_dir(out, true, {}, {{"solution_", ".vtu"}}); }),
                  "'.solution_3.vtu.partial' exists and was not written by hemicontact");
  fs::remove(out + "/.solution_3.vtu.partial");
  prepare_output_dir(out, false, {}, {{"solution_", ".vtu"}});
  EXPECT_EQ(read_text(out + "/solution_x.vtu"), "not a number: not a name the run writes\n");
}

}  // namespace
}  // namespace hemicontact
