// mesh/msh_peek.hpp: an MSH file's dimension and node count from its header alone (what
// solver.engine = auto sizes a Gmsh mesh by), in every format the importer reads, and nothing
// where the header cannot tell. Needs no Gmsh.

#include <hemicontact/mesh/msh_peek.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;
using namespace hemicontact;

namespace {

std::string peek_data(const std::string& name) { return std::string(HEMICONTACT_SOURCE_DIR "/tests/data/") + name; }

std::string peek_bytes(std::uint64_t v) { return std::string(reinterpret_cast<const char*>(&v), sizeof v); }

fs::path peek_write(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("hemicontact-msh-peek-" + std::to_string(::getpid()) + "-" + name);
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

const std::string PEEK_BINARY_ONE = std::string("\x01\x00\x00\x00", 4);  // the endianness check

}  // namespace

// The shipped test meshes: MSH 2.2 (dimension from $PhysicalNames) and 4.1 (from $Entities), ASCII.
TEST(MshPeek, ShippedMeshesGiveTheirDimensionAndNodeCount) {
  const struct {
    const char* file;
    int dim;
    double nodes;
  } cases[] = {{"plate_2x2.msh", 3, 243}, {"strip_4x1.msh", 2, 297}, {"unit_cube_6tets.msh", 3, 8},
               {"unit_square_3x3.msh", 2, 16}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file);
    const auto s = peek_msh_size(peek_data(c.file));
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->dim, c.dim);
    EXPECT_EQ(s->nodes, c.nodes);
  }
}

// Binary MSH 4.1: the counts are size_t, and the $Entities block may hold newline bytes.
TEST(MshPeek, BinaryFilesOfBothVersions) {
  const std::string v4 = "$MeshFormat\n4.1 1 8\n" + PEEK_BINARY_ONE + "\n$EndMeshFormat\n$Entities\n" + peek_bytes(8) +
                         peek_bytes(12) + peek_bytes(6) + peek_bytes(1) + std::string("\n\n\x07\n", 4) +
                         "\n$EndEntities\n$Nodes\n" + peek_bytes(10) + peek_bytes(1234) + peek_bytes(1) + peek_bytes(1234);
  const fs::path a = peek_write("v4.msh", v4);
  const auto s4 = peek_msh_size(a.string());
  ASSERT_TRUE(s4.has_value());
  EXPECT_EQ(s4->dim, 3);
  EXPECT_EQ(s4->nodes, 1234);
  const std::string v2 = "$MeshFormat\n2.2 1 8\n" + PEEK_BINARY_ONE +
                         "\n$EndMeshFormat\n$PhysicalNames\n2\n2 1 \"contact\"\n3 2 \"body\"\n$EndPhysicalNames\n"
                         "$Nodes\n77\n" + peek_bytes(1);
  const fs::path b = peek_write("v2.msh", v2);
  const auto s2 = peek_msh_size(b.string());
  ASSERT_TRUE(s2.has_value());
  EXPECT_EQ(s2->dim, 3);
  EXPECT_EQ(s2->nodes, 77);
  // The counts cut short: no size.
  const fs::path c = peek_write("cut.msh", v4.substr(0, v4.size() - 20));
  EXPECT_FALSE(peek_msh_size(c.string()).has_value());
  for (const fs::path& p : {a, b, c}) fs::remove(p);
}

// Where the header cannot tell, the answer is "unknown", never a guess: MSH 2 without physical
// names, MSH 4.0 (its counts are stored otherwise), a script, a missing file, a device, a folder.
TEST(MshPeek, NothingWhereTheHeaderCannotTell) {
  const fs::path no_names = peek_write("nonames.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n");
  const fs::path v40 = peek_write("v40.msh", "$MeshFormat\n4 0 8\n$EndMeshFormat\n$Entities\n1 0 0 1\n$EndEntities\n"
                                        "$Nodes\n1 4\n");
  const fs::path geo = peek_write("script.geo", "Point(1) = {0, 0, 0};\n$Nodes\n4\n");
  for (const std::string& p : {no_names.string(), v40.string(), geo.string(), peek_data("no-such-file.msh"),
                               std::string("/dev/zero"), fs::temp_directory_path().string()}) {
    SCOPED_TRACE(p);
    EXPECT_FALSE(peek_msh_size(p).has_value());
  }
  for (const fs::path& p : {no_names, v40, geo}) fs::remove(p);
}
