// mesh_to_bytes / mesh_from_bytes (mesh/mesh_bytes.hpp): every field comes back as written, and
// bytes that are not such a mesh are refused with an Error, never read out of bounds.
#include <hemicontact/mesh/mesh_bytes.hpp>

#include <hemicontact/core/error.hpp>

#include <gtest/gtest.h>

#include <string>

namespace hemicontact {
namespace {

// Two triangles with every optional field set: parts, a Γ2 load, a named group, a roller.
Mesh every_field() {
  Mesh m;
  m.dim = 2;
  m.points.resize(4, 2);
  m.points << 0, 0, 1, 0, 1, 1, 0, 1;
  m.cells.resize(2, 3);
  m.cells << 0, 1, 2, 0, 2, 3;
  m.facets.resize(4, 2);
  m.facets << 0, 1, 1, 2, 2, 3, 3, 0;
  m.facet_part = {Part::GAMMA3, Part::GAMMA2, Part::NONE, Part::GAMMA1};
  m.facet_load = {-1, 0, -1, -1};
  m.tractions = {Vec::Constant(2, -0.5)};
  m.facet_groups["bottom"] = {0};
  m.facet_groups["right"] = {1};
  m.node_fixed = {0, 1, 0, 0};
  m.origin = "two triangles";
  return m;
}

TEST(MeshBytes, EveryFieldComesBackAsWritten) {
  const Mesh a = every_field();
  const Mesh b = mesh_from_bytes(mesh_to_bytes(a));
  EXPECT_EQ(b.dim, a.dim);
  EXPECT_EQ(b.points, a.points);
  EXPECT_EQ(b.cells, a.cells);
  EXPECT_EQ(b.facets, a.facets);
  EXPECT_EQ(b.facet_part, a.facet_part);
  EXPECT_EQ(b.facet_load, a.facet_load);
  ASSERT_EQ(b.tractions.size(), 1u);
  EXPECT_EQ(b.tractions[0], a.tractions[0]);
  EXPECT_EQ(b.facet_groups, a.facet_groups);
  EXPECT_EQ(b.node_fixed, a.node_fixed);
  EXPECT_EQ(b.origin, a.origin);
  EXPECT_EQ(mesh_to_bytes(b), mesh_to_bytes(a));
}

TEST(MeshBytes, BytesThatAreNotAMeshAreRefused) {
  const std::string bytes = mesh_to_bytes(every_field());
  for (size_t n = 0; n < bytes.size(); ++n) EXPECT_THROW(mesh_from_bytes(bytes.substr(0, n)), Error) << n;
  EXPECT_THROW(mesh_from_bytes(bytes + "x"), Error);
  Mesh bad = every_field();
  bad.cells(1, 2) = 4;  // a fifth node that does not exist
  EXPECT_THROW(mesh_from_bytes(mesh_to_bytes(bad)), Error);
  bad = every_field();
  bad.facet_load[1] = 1;  // a second traction that does not exist
  EXPECT_THROW(mesh_from_bytes(mesh_to_bytes(bad)), Error);
  bad = every_field();
  bad.facet_part.pop_back();
  EXPECT_THROW(mesh_from_bytes(mesh_to_bytes(bad)), Error);
}

}  // namespace
}  // namespace hemicontact
