// Gmsh .msh import: nodes, cells, physical facet groups, selection by {"physical": ...}, the
// error messages, and a 3D tetrahedral mesh. Skipped when built without the Gmsh API.

#include <hemicontact/mesh/gmsh_import.hpp>

#include <hemicontact/config.hpp>
#include <hemicontact/contact/contact_nodes.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/material/linear_elastic.hpp>
#include <hemicontact/mesh/boundary.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

using namespace hemicontact;

namespace {

std::string data(const std::string& name) { return std::string(HEMICONTACT_SOURCE_DIR) + "/tests/data/" + name; }

#define SKIP_WITHOUT_GMSH()                                                                        \
  do {                                                                                             \
    if (!HEMICONTACT_HAS_GMSH) GTEST_SKIP() << "built without the Gmsh API (install libgmsh-dev)"; \
  } while (0)

// Message of the Error read_gmsh throws ("(no error)" if none).
std::string error_of(const std::string& path) {
  try {
    read_gmsh(path);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT);
    return e.what();
  }
  return "(no error)";
}

// read_gmsh with @p allow_scripts: the Error's message, or "(no error)".
std::string read_gmsh_or_error(const std::string& path, bool allow_scripts) {
  try {
    read_gmsh(path, allow_scripts);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

bool has_text(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

double group_measure(const Mesh& m, const std::string& name) {
  double s = 0;
  for (Index f : m.facet_groups.at(name)) s += m.facet_measure(f);
  return s;
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

// Coordinates in the files are written with 16 significant digits (1/3 → 0.3333333333333333), so
// lengths and areas built from them are exact to a few ulps: 1e-14.
constexpr double TOL = 1e-14;

}  // namespace

// tests/data/unit_square_3x3.msh: 16 nodes, 18 triangles, 12 boundary edges; physical lines
// "clamped" (top, 3 edges), "load" (left + right, 6), "contact" (bottom, 3), unnamed tag 11
// (left, 3); the physical surface "body" is not a facet group.
TEST(GmshImport, UnitSquare) {
  SKIP_WITHOUT_GMSH();
  const Mesh m = read_gmsh(data("unit_square_3x3.msh"));
  EXPECT_EQ(m.dim, 2);
  EXPECT_EQ(m.num_nodes(), 16);
  EXPECT_EQ(m.num_cells(), 18);
  EXPECT_EQ(m.num_facets(), 12);
  EXPECT_TRUE(has_text(m.origin, "unit_square_3x3.msh"));
  double area = 0;
  for (Index c = 0; c < m.num_cells(); ++c) {
    EXPECT_GT(m.cell_measure(c), 0.0) << "cell " << c;
    area += m.cell_measure(c);
  }
  EXPECT_NEAR(area, 1.0, TOL);
  EXPECT_NO_THROW(check_cells(m));
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(m.points.col(k).minCoeff(), 0.0);
    EXPECT_EQ(m.points.col(k).maxCoeff(), 1.0);
  }

  ASSERT_EQ(m.facet_groups.size(), 4u);
  EXPECT_EQ(m.facet_groups.at("clamped").size(), 3u);
  EXPECT_EQ(m.facet_groups.at("load").size(), 6u);
  EXPECT_EQ(m.facet_groups.at("contact").size(), 3u);
  EXPECT_EQ(m.facet_groups.at("11").size(), 3u);
  EXPECT_EQ(m.facet_groups.count("body"), 0u);
  EXPECT_NEAR(group_measure(m, "clamped"), 1.0, TOL);
  EXPECT_NEAR(group_measure(m, "load"), 2.0, TOL);
  EXPECT_NEAR(group_measure(m, "contact"), 1.0, TOL);
  EXPECT_NEAR(group_measure(m, "11"), 1.0, TOL);
  // The groups point at the right boundary facets: outward normals (0, −1) on "contact",
  // (0, 1) on "clamped", (−1, 0) on the left side (group 11).
  for (Index f : m.facet_groups.at("contact")) EXPECT_NEAR((m.facet_normal(f) - Vec::Unit(2, 1) * -1).norm(), 0, TOL);
  for (Index f : m.facet_groups.at("clamped")) EXPECT_NEAR((m.facet_normal(f) - Vec::Unit(2, 1)).norm(), 0, TOL);
  for (Index f : m.facet_groups.at("11")) EXPECT_NEAR((m.facet_normal(f) - Vec::Unit(2, 0) * -1).norm(), 0, TOL);
}

// {"physical": name} selectors tag the groups; the contact nodes on "contact" are the 4 bottom
// nodes with weights h/2, h, h, h/2 (h = 1/3), normal (0, −1).
TEST(GmshImport, PhysicalSelectors) {
  SKIP_WITHOUT_GMSH();
  Mesh m = read_gmsh(data("unit_square_3x3.msh"));
  const auto physical = [](const std::string& name, const std::string& context) {
    BoundarySelector s;
    s.physical = name;
    s.context = context;
    return s;
  };
  BoundarySpec spec;
  spec.gamma1 = {physical("clamped", "boundary.gamma1[0]")};
  spec.gamma2 = {physical("load", "boundary.gamma2[0]")};
  spec.gamma2[0].traction = (Vec(2) << 1.0, 0.0).finished();
  spec.gamma3 = {physical("contact", "boundary.gamma3[0]")};
  assign_boundary(m, spec);
  int n1 = 0, n2 = 0, n3 = 0;
  for (Part p : m.facet_part) {
    n1 += p == Part::GAMMA1;
    n2 += p == Part::GAMMA2;
    n3 += p == Part::GAMMA3;
  }
  EXPECT_EQ(n1, 3);
  EXPECT_EQ(n2, 6);
  EXPECT_EQ(n3, 3);
  Gap gap;
  gap.constant = 0.15;
  const ContactNodes c = make_contact_nodes(m, clamped_nodes(m), gap);
  ASSERT_EQ(c.size(), 4);
  const double h = 1.0 / 3;
  for (Index i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.points(c.node[i], 0), i * h, TOL);
    EXPECT_NEAR(c.w[i], (i == 0 || i == 3) ? h / 2 : h, TOL);
    EXPECT_NEAR(c.normal(i, 1), -1.0, TOL);
  }
  // Group "11" overlaps "load" on the left side: selecting both is an overlap error.
  spec.gamma3.push_back(physical("11", "boundary.gamma3[1]"));
  EXPECT_THROW(assign_boundary(m, spec), Error);
  // An interval cannot restrict a group (it is measured along a side): refused, not ignored.
  spec.gamma3 = {physical("contact", "boundary.gamma3[0]")};
  spec.gamma3[0].from = 100;
  spec.gamma3[0].to = 200;
  std::string e = "(no error)";
  try {
    assign_boundary(m, spec);
  } catch (const Error& err) {
    e = err.what();
  }
  EXPECT_TRUE(has_text(e, "boundary.gamma3[0]: an interval [from, to) restricts a 'side' selector only")) << e;
}

// tests/data/unit_square_3x3_interior_contact.msh: "contact" also holds the edge (5, 12), a
// chord between two boundary nodes through the body, which is not part of ∂Ω.
TEST(GmshImport, ContactGroupWithInteriorFacetIsRejected) {
  SKIP_WITHOUT_GMSH();
  const std::string e = error_of(data("unit_square_3x3_interior_contact.msh"));
  EXPECT_TRUE(has_text(e, "unit_square_3x3_interior_contact.msh")) << e;
  EXPECT_TRUE(has_text(e, "physical group 'contact' contains facet (5, 12) which is not on the boundary")) << e;
}

TEST(GmshImport, UnreadableFilesNameTheFile) {
  SKIP_WITHOUT_GMSH();
  std::string e = error_of(data("no_such_file.msh"));
  EXPECT_TRUE(has_text(e, "no_such_file.msh") && has_text(e, "cannot open")) << e;

  const std::string garbage = write_temp("hemicontact_garbage.msh", "this is not a mesh\n");
  e = error_of(garbage);
  EXPECT_TRUE(has_text(e, "gmsh file '" + garbage + "'")) << e;

  // A valid file with a line element but no triangles.
  const std::string lines = write_temp("hemicontact_lines_only.msh",
                                       "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                                       "$Nodes\n1 2 1 2\n1 1 0 2\n1\n2\n0 0 0\n1 0 0\n$EndNodes\n"
                                       "$Elements\n1 1 1 1\n1 1 1 1\n1 1 2\n$EndElements\n");
  e = error_of(lines);
  EXPECT_TRUE(has_text(e, "hemicontact_lines_only.msh") && has_text(e, "no triangles")) << e;

  // Quadrilateral cells are not P1 triangles.
  const std::string quad = write_temp("hemicontact_quad.msh",
                                      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                                      "$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n"
                                      "$Elements\n1 1 1 1\n2 1 3 1\n1 1 2 3 4\n$EndElements\n");
  e = error_of(quad);
  EXPECT_TRUE(has_text(e, "hemicontact_quad.msh") && has_text(e, "MSH type 3") && has_text(e, "triangles")) << e;
}

// tests/data/unit_cube_6tets.msh: the unit cube as 6 tetrahedra (8 nodes), physical surface
// "bottom" (z = 0, 2 triangles). Also a 3D check of the P1 stiffness: for a linear u,
// ½ uᵀ K u = ½ |Ω| ε : D ε, and the 6 rigid motions are in the kernel (round-off: 1e-12, as in
// tests/fem/assembly_test.cpp).
TEST(GmshImport, UnitCubeTetrahedra) {
  SKIP_WITHOUT_GMSH();
  const Mesh m = read_gmsh(data("unit_cube_6tets.msh"));
  EXPECT_EQ(m.dim, 3);
  EXPECT_EQ(m.num_nodes(), 8);
  EXPECT_EQ(m.num_cells(), 6);
  EXPECT_EQ(m.num_facets(), 12);
  double vol = 0;
  for (Index c = 0; c < m.num_cells(); ++c) {
    EXPECT_GT(m.cell_measure(c), 0.0);
    vol += m.cell_measure(c);
  }
  EXPECT_NEAR(vol, 1.0, TOL);
  ASSERT_EQ(m.facet_groups.size(), 1u);
  ASSERT_EQ(m.facet_groups.at("bottom").size(), 2u);
  EXPECT_NEAR(group_measure(m, "bottom"), 1.0, TOL);
  for (Index f : m.facet_groups.at("bottom")) EXPECT_NEAR((m.facet_normal(f) + Vec::Unit(3, 2)).norm(), 0, TOL);

  const LinearElastic mat(2000, 0.3, PlaneMode::NONE_3D);
  const SpMat K = assemble_stiffness(m, mat);
  Eigen::Matrix3d A;
  A << 0.3, -0.7, 0.1, 0.45, 0.2, -0.25, 0.05, 0.6, -0.4;
  Vec u(24);
  for (Index a = 0; a < 8; ++a) u.segment<3>(3 * a) = A * m.points.row(a).transpose();
  Vec eps(6);  // Voigt (ε11, ε22, ε33, 2ε23, 2ε13, 2ε12)
  eps << A(0, 0), A(1, 1), A(2, 2), A(1, 2) + A(2, 1), A(0, 2) + A(2, 0), A(0, 1) + A(1, 0);
  const double want = 0.5 * eps.dot(mat.D() * eps);
  EXPECT_NEAR(0.5 * u.dot(K * u), want, 1e-12 * want);
  const double kmax = Mat(K).cwiseAbs().rowwise().sum().maxCoeff();
  for (int k = 0; k < 6; ++k) {
    Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    if (k < 3) {
      t[k] = 1;
    } else {  // rotation about axis k − 3: skew matrix
      const int i = (k - 3 + 1) % 3, j = (k - 3 + 2) % 3;
      R(i, j) = -1;
      R(j, i) = 1;
    }
    Vec r(24);
    for (Index a = 0; a < 8; ++a) r.segment<3>(3 * a) = R * m.points.row(a).transpose() + t;
    EXPECT_LE((K * r).lpNorm<Eigen::Infinity>(), 1e-12 * kmax * r.lpNorm<Eigen::Infinity>()) << "rigid motion " << k;
  }
}

// Without Gmsh, read_gmsh exists and says how to get it.
TEST(GmshImport, FallbackWithoutGmsh) {
  if (HEMICONTACT_HAS_GMSH) GTEST_SKIP() << "built with the Gmsh API; the fallback is not compiled";
  const std::string e = error_of(data("unit_square_3x3.msh"));
  EXPECT_TRUE(has_text(e, "not compiled in") && has_text(e, "libgmsh-dev")) << e;
}

// Gmsh picks a file's format from its content and runs anything that is not a mesh as
// a script: a file named evil.msh holding `SystemCall "touch PATH";` ran the command, and
// `Printf(...) > "PATH";` wrote files. Without allow_scripts the MSH header is checked before Gmsh
// sees the file; the script does nothing and the message names mesh.allow_scripts.
TEST(GmshImport, ScriptsAreNotRunWithoutOptIn) {
  SKIP_WITHOUT_GMSH();
  const std::string touched = ::testing::TempDir() + "hemicontact_gmsh_touched";
  const std::string printed = ::testing::TempDir() + "hemicontact_gmsh_printed";
  std::remove(touched.c_str());
  std::remove(printed.c_str());
  const std::string script = "SystemCall \"touch " + touched + "\";\nPrintf(\"x\") > \"" + printed + "\";\n";
  for (const char* name : {"evil.msh", "evil.txt"}) {
    SCOPED_TRACE(name);
    const std::string e = error_of(write_temp(name, script));
    EXPECT_TRUE(has_text(e, "not a Gmsh mesh") && has_text(e, "mesh.allow_scripts")) << e;
    EXPECT_TRUE(has_text(e, "first line is 'SystemCall \"touch")) << e;
  }
  // A valid header followed by script commands: read as MSH (an unknown section or a parse
  // failure), never run.
  error_of(write_temp("evil2.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n" + script));
  // Gmsh parses a .geo file as a script whatever its first line: refused by the extension.
  EXPECT_TRUE(has_text(error_of(write_temp("evil2.geo", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n" + script)),
                       "a Gmsh script by its extension (.geo)"));
  EXPECT_FALSE(std::ifstream(touched).good()) << "a SystemCall ran";
  EXPECT_FALSE(std::ifstream(printed).good()) << "a Printf wrote a file";
  // With the opt-in, Gmsh gets the script (and runs it: that is what allow_scripts says it does).
  (void)read_gmsh_or_error(write_temp("trusted.geo", "Printf(\"x\") > \"" + printed + "\";\n"), true);
  EXPECT_TRUE(std::ifstream(printed).good()) << "allow_scripts did not pass the script to Gmsh";
  std::remove(printed.c_str());
}

// Gmsh merges <file>.opt after opening any file, and an .opt file is a script: a m.msh.opt holding
// SystemCall beside a valid m.msh ran the command. Without allow_scripts Gmsh opens a
// private copy, so the planted .opt is never read and the mesh is read as before.
TEST(GmshImport, CompanionOptFileIsNotRun) {
  SKIP_WITHOUT_GMSH();
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "hemicontact_gmsh_opt";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string mesh = (dir / "m.msh").string();
  std::filesystem::copy_file(data("unit_square_3x3.msh"), mesh);
  const std::string pwned = (dir / "pwned").string();
  std::ofstream(mesh + ".opt") << "SystemCall \"touch " << pwned << "\";\n";
  const Mesh m = read_gmsh(mesh);
  EXPECT_EQ(m.num_nodes(), 16);
  EXPECT_FALSE(std::filesystem::exists(pwned)) << "Gmsh ran the .opt file beside the mesh";
  // The check above can fail: with the opt-in, Gmsh opens the file itself and runs its .opt.
  (void)read_gmsh(mesh, true);
  EXPECT_TRUE(std::filesystem::exists(pwned)) << "Gmsh did not read the planted .opt (the test proves nothing)";
  std::filesystem::remove_all(dir);
}

// The header check accepts what Gmsh writes (MSH 2.x and 4.x, ASCII and binary; leading blank
// lines) and refuses other versions and file types, naming them.
TEST(GmshImport, MshHeaderCheck) {
  SKIP_WITHOUT_GMSH();
  const std::string body = "$EndMeshFormat\n";
  for (const char* header : {"$MeshFormat\n2.2 0 8\n", "\n  \n$MeshFormat\r\n4.1 1 8\r\n", "$MeshFormat\n4 0 8\n"}) {
    const std::string e = error_of(write_temp("header.msh", header + body));
    EXPECT_FALSE(has_text(e, "not a Gmsh mesh") || has_text(e, "unsupported MSH header")) << header << ": " << e;
  }
  EXPECT_TRUE(has_text(error_of(write_temp("v3.msh", "$MeshFormat\n3.0 0 8\n" + body)), "unsupported MSH header '3.0 0 8'"));
  EXPECT_TRUE(has_text(error_of(write_temp("t2.msh", "$MeshFormat\n4.1 2 8\n" + body)), "file type 0 (ASCII) or"));
  EXPECT_TRUE(has_text(error_of(write_temp("empty.msh", "")), "first line is ''"));
  // The real files of tests/data pass (UnitSquare and UnitCube read them in full).
  EXPECT_EQ(error_of(data("unit_square_3x3.msh")), "(no error)");
  // Not a regular file: refused by its kind before it is opened (a FIFO would block).
  EXPECT_TRUE(has_text(error_of("/dev/zero"), "not a regular file"));
}
