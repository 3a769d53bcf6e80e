#include <hemicontact/mesh/msh_peek.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hemicontact {
namespace {

constexpr std::streamoff MAX_SCAN = std::streamoff(64) << 20;  // the sections before $Nodes are small

std::string trimmed(const std::string& t) {
  const size_t a = t.find_first_not_of(" \t\r"), b = t.find_last_not_of(" \t\r");
  return a == std::string::npos ? std::string() : t.substr(a, b - a + 1);
}

// The MSH format's facts that decide how its counts are stored.
struct MshFormat {
  int major = 0;  // 2 or 4 (4.1); 0: not read or not supported
  bool binary = false;
};

MshFormat read_format(std::istream& in) {
  std::string line;
  if (!std::getline(in, line)) return {};
  std::istringstream f(line);
  std::string version;
  int file_type = -1, data_size = 0;
  f >> version >> file_type >> data_size;
  if (!f || (file_type != 0 && file_type != 1) || (file_type == 1 && data_size != 8)) return {};
  if (version.rfind("2", 0) == 0) return {2, file_type == 1};
  if (version == "4.1") return {4, file_type == 1};
  return {};  // 4.0 stores its counts otherwise
}

// Four counts as MSH 4.1 writes them at the head of $Entities and $Nodes: one ASCII line, or four
// binary size_t (data size 8, as read_format requires).
bool read_counts(std::istream& in, bool binary, std::uint64_t (&c)[4]) {
  if (binary) {
    in.read(reinterpret_cast<char*>(c), sizeof c);
    return static_cast<size_t>(in.gcount()) == sizeof c;
  }
  std::string line;
  if (!std::getline(in, line)) return false;
  std::istringstream f(line);
  return static_cast<bool>(f >> c[0] >> c[1] >> c[2] >> c[3]);
}

// $PhysicalNames (ASCII in both formats): "count", then "dim tag "name"" per group.
int physical_dim(std::istream& in) {
  std::string line;
  int count = 0, dim = 0;
  if (!std::getline(in, line) || !(std::istringstream(line) >> count)) return 0;
  for (int k = 0; k < count && std::getline(in, line); ++k) {
    int d = 0;
    if (std::istringstream(line) >> d) dim = std::max(dim, d);
  }
  return dim;
}

}  // namespace

std::optional<MshSize> peek_msh_size(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  MshFormat fmt;
  MshSize s;
  std::string line;
  while (std::getline(in, line) && in.tellg() < MAX_SCAN) {
    line = trimmed(line);
    if (line == "$MeshFormat") {
      fmt = read_format(in);
      if (fmt.major == 0) return std::nullopt;
    } else if (line == "$PhysicalNames" && fmt.major == 2) {
      s.dim = std::max(s.dim, physical_dim(in));
    } else if (line == "$Entities" && fmt.major == 4) {
      std::uint64_t c[4];  // points, curves, surfaces, volumes
      if (!read_counts(in, fmt.binary, c)) return std::nullopt;
      s.dim = c[3] ? 3 : c[2] ? 2 : c[1] ? 1 : 0;
    } else if (line == "$Nodes" && fmt.major != 0) {
      std::uint64_t c[4] = {0, 0, 0, 0};  // MSH 4.1: blocks, nodes, min tag, max tag
      if (fmt.major == 4 ? !read_counts(in, fmt.binary, c) : !(std::getline(in, line) &&
                                                                 std::istringstream(line) >> c[1]))
        return std::nullopt;
      s.nodes = static_cast<double>(c[1]);
      if (s.dim == 0) return std::nullopt;
      return s;
    }
  }
  return std::nullopt;
}

}  // namespace hemicontact
