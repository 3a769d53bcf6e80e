#include <hemicontact/mesh/gmsh_import.hpp>

#include <hemicontact/core/error.hpp>

#include <dlfcn.h>
#include <gmshc.h>  // the C API's declarations only: libgmsh is opened at run time, not linked

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <utility>
#include <vector>

// Compiled only when the Gmsh API was found (CMake globs src/mesh/gmsh_*.cpp then); the fallback
// read_gmsh() of other builds lives in mesh_io.cpp.
//
// Why dlopen: linking libgmsh pulls in ~90 shared libraries (OpenCASCADE, FLTK, MED, ...) whose
// loading and relocation cost ~80 ms at every start of the program, also for the scenes that never
// read a .msh file (all generated meshes), i.e. 15 % of the whole default run at h = 1/256. Gmsh's
// C API (gmshc.h) has plain C symbols, so the few functions used here are looked up once with dlsym
// when the first .msh file is read.

namespace hemicontact {
namespace {

// Every Gmsh function this file calls; GmshApi holds one pointer per entry.
#define HEMICONTACT_GMSH_FUNCTIONS(X)                                                                  \
  X(gmshFree)                                                                                          \
  X(gmshInitialize)                                                                                    \
  X(gmshFinalize)                                                                                      \
  X(gmshOpen)                                                                                          \
  X(gmshOptionSetNumber)                                                                               \
  X(gmshModelGetPhysicalGroups)                                                                        \
  X(gmshModelGetEntitiesForPhysicalGroup)                                                              \
  X(gmshModelGetPhysicalName)                                                                          \
  X(gmshModelMeshGetNodes)                                                                             \
  X(gmshModelMeshGetElements)                                                                          \
  X(gmshModelMeshGetElementProperties)                                                                 \
  X(gmshLoggerGetLastError)

struct GmshApi {
#define HEMICONTACT_GMSH_POINTER(name) decltype(&::name) name = nullptr;
  HEMICONTACT_GMSH_FUNCTIONS(HEMICONTACT_GMSH_POINTER)
#undef HEMICONTACT_GMSH_POINTER
};

// The library by its soname (the dynamic loader's search, as a linked program would), then by the
// path found at configure time. It is never closed: Gmsh keeps process-wide state.
GmshApi load_gmsh() {
  const char* candidates[] = {HEMICONTACT_GMSH_SONAME, HEMICONTACT_GMSH_LIBRARY_PATH};
  void* lib = nullptr;
  std::string reasons;
  for (const char* name : candidates) {
    if ((lib = dlopen(name, RTLD_NOW | RTLD_LOCAL)) != nullptr) break;
    const char* why = dlerror();
    reasons += std::string(reasons.empty() ? "" : "; ") + (why ? why : name);
  }
  if (!lib)
    throw Error("Gmsh .msh import: the Gmsh library could not be loaded (" + reasons +
                "); install libgmsh-dev (scripts/install-deps.sh) or use a generated mesh");
  GmshApi api;
#define HEMICONTACT_GMSH_LOOKUP(name)                                                                       \
  api.name = reinterpret_cast<decltype(&::name)>(dlsym(lib, #name));                                     \
  if (!api.name)                                                                                         \
    throw Error(std::string("Gmsh .msh import: the Gmsh library has no function " #name " (Gmsh ") +      \
                HEMICONTACT_GMSH_SONAME + " was expected)");
  HEMICONTACT_GMSH_FUNCTIONS(HEMICONTACT_GMSH_LOOKUP)
#undef HEMICONTACT_GMSH_LOOKUP
  return api;
}

const GmshApi& gmsh() {
  static const GmshApi api = load_gmsh();  // a failed load throws and is tried again next time
  return api;
}

// A Gmsh C call failed (ierr != 0): read_gmsh() turns it into an input error with Gmsh's last
// logged message.
struct GmshFailure {
  std::string call;
};

void check(int ierr, const char* call) {
  if (ierr != 0) throw GmshFailure{call};
}

// Copies a Gmsh-allocated array into a vector and frees it.
template <class T>
std::vector<T> take(T* p, std::size_t n) {
  std::vector<T> v(p, p + (p ? n : 0));
  gmsh().gmshFree(p);
  return v;
}

std::string take_string(char* p) {
  std::string s(p ? p : "");
  gmsh().gmshFree(p);
  return s;
}

// Gmsh is a process-wide singleton: finalize() must run on every exit path, including failures.
// User configuration files are not read so that the result does not depend on ~/.gmshrc.
class GmshSession {
 public:
  GmshSession() {
    int ierr = 0;
    gmsh().gmshInitialize(0, nullptr, /*readConfigFiles=*/0, &ierr);
    if (ierr != 0) throw Error("Gmsh .msh import: Gmsh could not be initialized");
    gmsh().gmshOptionSetNumber("General.Terminal", 0, &ierr);
  }
  ~GmshSession() {
    int ierr = 0;
    gmsh().gmshFinalize(&ierr);  // nothing useful can be done with a failure here
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

// The elements of dimension dim (and entity tag, −1 for all): their types and, per type, the node
// tags of every element.
struct Elements {
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> nodes;
};

Elements get_elements(int dim, int tag) {
  int* types = nullptr;
  std::size_t n_types = 0, **elem_tags = nullptr, *elem_tags_n = nullptr, n_elem_tags = 0;
  std::size_t **node_tags = nullptr, *node_tags_n = nullptr, n_node_tags = 0;
  int ierr = 0;
  gmsh().gmshModelMeshGetElements(&types, &n_types, &elem_tags, &elem_tags_n, &n_elem_tags, &node_tags, &node_tags_n,
                                  &n_node_tags, dim, tag, &ierr);
  Elements e;
  e.types = take(types, ierr ? 0 : n_types);
  for (std::size_t t = 0; t < n_elem_tags; ++t) gmsh().gmshFree(elem_tags[t]);
  for (std::size_t t = 0; t < n_node_tags; ++t) e.nodes.push_back(take(node_tags[t], node_tags_n[t]));
  gmsh().gmshFree(elem_tags);
  gmsh().gmshFree(elem_tags_n);
  gmsh().gmshFree(node_tags);
  gmsh().gmshFree(node_tags_n);
  check(ierr, "model::mesh::getElements");
  return e;
}

// Sorted node indices of a facet (third entry −1 in 2D): the key under which it is looked up.
using FacetKey = std::array<int, 3>;

FacetKey sorted_key(const int* v, int n) {
  FacetKey k{-1, -1, -1};
  // A facet has 2 (2D) or 3 (3D) nodes: a sorting network of compare-swaps (std::sort on a range
  // whose length the compiler cannot bound drew a false -Warray-bounds from its insertion sort).
  const int m = n == 3 ? 3 : 2;
  std::copy(v, v + m, k.begin());
  const auto order = [&k](int i, int j) {
    if (k[static_cast<size_t>(i)] > k[static_cast<size_t>(j)]) std::swap(k[static_cast<size_t>(i)], k[static_cast<size_t>(j)]);
  };
  order(0, 1);
  if (m == 3) order(1, 2), order(0, 1);
  return k;
}

std::string element_name(int type) {
  char* name = nullptr;
  double* local = nullptr;
  std::size_t n_local = 0;
  int dim = 0, order = 0, num_nodes = 0, num_primary = 0, ierr = 0;
  gmsh().gmshModelMeshGetElementProperties(type, &name, &dim, &order, &num_nodes, &local, &n_local, &num_primary,
                                           &ierr);
  gmsh().gmshFree(local);
  return take_string(name) + " (MSH type " + std::to_string(type) + ")";
}

// The cells of the model: tetrahedra make it 3D, otherwise triangles make it 2D.
struct ModelCells {
  int dim = 3;
  std::vector<std::size_t> nodes;  // Gmsh node tags, dim + 1 per cell
};

ModelCells read_cells(const std::string& where) {
  ModelCells cells;
  Elements elements = get_elements(3, -1);
  if (elements.types.empty()) {
    cells.dim = 2;
    elements = get_elements(2, -1);
  }
  const int dim = cells.dim;
  const std::vector<int>& types = elements.types;
  const std::vector<std::vector<std::size_t>>& elem_nodes = elements.nodes;
  if (types.empty()) input_error(where + "no triangles or tetrahedra (was the mesh generated, e.g. with gmsh -2?)");
  const int cell_type = dim == 2 ? 2 : 4;
  for (std::size_t t = 0; t < types.size(); ++t) {
    if (types[t] != cell_type)
      input_error(where + "contains " + element_name(types[t]) + " cells; only " +
                  (dim == 2 ? "3-node triangles" : "4-node tetrahedra") + " are supported");
    cells.nodes.insert(cells.nodes.end(), elem_nodes[t].begin(), elem_nodes[t].end());
  }
  return cells;
}

// Coordinates of every node, then a renumbering of the nodes the cells use (increasing tag): sets
// m.points and returns the index of each used tag.
std::unordered_map<std::size_t, int> read_points(const std::string& where, const std::vector<std::size_t>& cell_nodes,
                                                 Mesh& m) {
  const int dim = m.dim;
  int ierr = 0;
  std::size_t *node_tags_p = nullptr, n_node_tags = 0, n_coord = 0, n_param = 0;
  double *coord_p = nullptr, *param_p = nullptr;
  gmsh().gmshModelMeshGetNodes(&node_tags_p, &n_node_tags, &coord_p, &n_coord, &param_p, &n_param, -1, -1, 0, 0, &ierr);
  const std::vector<std::size_t> node_tags = take(node_tags_p, n_node_tags);
  const std::vector<double> coord = take(coord_p, n_coord);
  gmsh().gmshFree(param_p);
  check(ierr, "model::mesh::getNodes");
  if (coord.size() != 3 * node_tags.size()) input_error(where + "Gmsh returned inconsistent node coordinates");
  std::unordered_map<std::size_t, std::size_t> row_of_tag;  // tag → position in node_tags
  for (std::size_t i = 0; i < node_tags.size(); ++i) row_of_tag[node_tags[i]] = i;
  std::vector<std::size_t> used(cell_nodes);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::unordered_map<std::size_t, int> index_of_tag;
  for (std::size_t i = 0; i < used.size(); ++i) index_of_tag[used[i]] = static_cast<int>(i);

  m.points.resize(static_cast<Index>(used.size()), dim);
  double extent = 0;
  for (std::size_t i = 0; i < used.size(); ++i) {
    const auto it = row_of_tag.find(used[i]);
    if (it == row_of_tag.end()) input_error(where + "a cell uses the undefined node " + std::to_string(used[i]));
    for (int k = 0; k < 3; ++k) extent = std::max(extent, std::abs(coord[3 * it->second + k]));
    for (int k = 0; k < dim; ++k) m.points(static_cast<Index>(i), k) = coord[3 * it->second + k];
  }
  if (dim == 2) {
    // A 2D model must be in the plane z = 0; anything above round-off of the coordinates is a
    // surface elsewhere in space, which the plane-stress model cannot represent.
    for (std::size_t i = 0; i < used.size(); ++i) {
      const double z = coord[3 * row_of_tag[used[i]] + 2];
      if (std::abs(z) > 1e-12 * std::max(extent, 1.0)) {
        std::ostringstream os;
        os << where << "2D mesh is not in the plane z = 0 (node " << used[i] << " has z = " << z << ")";
        input_error(os.str());
      }
    }
  }
  return index_of_tag;
}

// Appends to @p members the boundary facets of entity @p ent of a physical group.
void read_group_facets(const std::string& where, const std::string& name, int gdim, int ent, int dim,
                       const std::unordered_map<std::size_t, int>& index_of_tag,
                       const std::map<FacetKey, Index>& boundary, std::vector<Index>& members) {
  const int facet_type = dim == 2 ? 1 : 2;
  const Elements facets = get_elements(gdim, ent);
  for (std::size_t t = 0; t < facets.types.size(); ++t) {
    if (facets.types[t] != facet_type)
      input_error(where + "physical group '" + name + "' contains " + element_name(facets.types[t]) +
                  " elements; only " + (dim == 2 ? "2-node lines" : "3-node triangles") + " are supported");
    const auto& nodes = facets.nodes[t];
    for (std::size_t e = 0; e + dim <= nodes.size(); e += dim) {
      int v[3] = {-1, -1, -1};
      bool known = true;
      for (int a = 0; a < dim; ++a) {
        const auto it = index_of_tag.find(nodes[e + a]);
        known = known && it != index_of_tag.end();
        if (known) v[a] = it->second;
      }
      const auto hit = known ? boundary.find(sorted_key(v, dim)) : boundary.end();
      if (hit == boundary.end()) {
        std::ostringstream os;
        os << where << "physical group '" << name << "' contains facet (" << nodes[e];
        for (int a = 1; a < dim; ++a) os << ", " << nodes[e + a];
        os << ") which is not on the boundary";
        input_error(os.str());
      }
      members.push_back(hit->second);
    }
  }
}

// Physical groups of dimension d−1 → named facet groups.
void read_facet_groups(const std::string& where, const std::unordered_map<std::size_t, int>& index_of_tag, Mesh& m) {
  const int dim = m.dim;
  int ierr = 0;
  std::map<FacetKey, Index> boundary;
  for (Index f = 0; f < m.num_facets(); ++f) boundary[sorted_key(&m.facets(f, 0), dim)] = f;

  int* dim_tags_p = nullptr;
  std::size_t n_dim_tags = 0;
  gmsh().gmshModelGetPhysicalGroups(&dim_tags_p, &n_dim_tags, dim - 1, &ierr);
  const std::vector<int> dim_tags = take(dim_tags_p, n_dim_tags);  // (dim, tag) pairs
  check(ierr, "model::getPhysicalGroups");
  for (std::size_t g = 0; g + 1 < dim_tags.size(); g += 2) {
    const int gdim = dim_tags[g], gtag = dim_tags[g + 1];
    char* name_p = nullptr;
    gmsh().gmshModelGetPhysicalName(gdim, gtag, &name_p, &ierr);
    std::string name = take_string(name_p);
    check(ierr, "model::getPhysicalName");
    if (name.empty()) name = std::to_string(gtag);
    if (m.facet_groups.count(name)) input_error(where + "two physical groups are named '" + name + "'");
    std::vector<Index>& members = m.facet_groups[name];
    int* entities_p = nullptr;
    std::size_t n_entities = 0;
    gmsh().gmshModelGetEntitiesForPhysicalGroup(gdim, gtag, &entities_p, &n_entities, &ierr);
    const std::vector<int> entities = take(entities_p, n_entities);
    check(ierr, "model::getEntitiesForPhysicalGroup");
    for (int ent : entities) read_group_facets(where, name, gdim, ent, dim, index_of_tag, boundary, members);
    // A facet may be listed by two entities of one group; each facet counts once.
    std::sort(members.begin(), members.end());
    members.erase(std::unique(members.begin(), members.end()), members.end());
  }
}

// @p path names the file in messages; Gmsh opens @p open_path (the same file, or its private copy).
Mesh read_model(const std::string& path, const std::string& open_path) {
  const std::string where = "gmsh file '" + path + "': ";
  int ierr = 0;
  gmsh().gmshOpen(open_path.c_str(), &ierr);
  check(ierr, "open");

  const ModelCells cells = read_cells(where);
  const int dim = cells.dim, nv = dim + 1;
  const std::vector<std::size_t>& cell_nodes = cells.nodes;
  Mesh m;
  m.dim = dim;
  m.origin = "gmsh " + path;
  std::unordered_map<std::size_t, int> index_of_tag = read_points(where, cell_nodes, m);

  const Index n_cells = static_cast<Index>(cell_nodes.size() / nv);
  m.cells.resize(n_cells, nv);
  for (Index c = 0; c < n_cells; ++c)
    for (int a = 0; a < nv; ++a) m.cells(c, a) = index_of_tag[cell_nodes[static_cast<std::size_t>(c * nv + a)]];
  // Gmsh orients cells by the geometry's parametrization, not necessarily counter-clockwise;
  // swapping two nodes flips the sign of the measure.
  for (Index c = 0; c < n_cells; ++c)
    if (m.cell_measure(c) < 0) std::swap(m.cells(c, 1), m.cells(c, 2));
  try {
    check_cells(m);
    extract_boundary_facets(m);
  } catch (const Error& e) {
    input_error(where + e.what());
  }
  read_facet_groups(where, index_of_tag, m);
  return m;
}

// A copy of a mesh file as mesh.msh in a new folder only this user can enter (mkdtemp, mode 0700),
// removed with the object: Gmsh opening it finds no companion file (mesh.msh.opt) to run. A fixed
// name with the .msh extension, so that Gmsh reads it as a mesh whatever the original was called
// (a .gz name would make Gmsh run gunzip).
class PrivateCopy {
 public:
  explicit PrivateCopy(const std::string& path) {
    std::string dir = (std::filesystem::temp_directory_path() / "hemicontact-gmsh-XXXXXX").string();
    if (mkdtemp(dir.data()) == nullptr)
      throw Error("Gmsh .msh import: cannot create a private temporary folder in " +
                  std::filesystem::temp_directory_path().string() + " (TMPDIR): " + std::strerror(errno));
    m_dir = dir;
    std::error_code ec;
    std::filesystem::copy_file(path, m_dir / "mesh.msh", ec);
    if (ec) {
      const std::string why = ec.message();
      std::filesystem::remove_all(m_dir, ec);  // the destructor does not run for a throwing constructor
      input_error("gmsh file '" + path + "': cannot copy it for reading (" + why + ")");
    }
  }
  ~PrivateCopy() {
    std::error_code ec;
    std::filesystem::remove_all(m_dir, ec);  // a leftover temporary folder is not worth an error
  }
  PrivateCopy(const PrivateCopy&) = delete;
  PrivateCopy& operator=(const PrivateCopy&) = delete;
  std::string file() const { return (m_dir / "mesh.msh").string(); }

 private:
  std::filesystem::path m_dir;
};

// The header of an MSH file, version 2.x or 4.x, ASCII or binary: the first non-blank line is
// "$MeshFormat", the next "VERSION FILE-TYPE DATA-SIZE" with FILE-TYPE 0 (ASCII) or 1 (binary).
// Gmsh reads such a file as a mesh (its unknown sections are skipped, never run). Only a bounded
// prefix is read, and only from a regular file (a FIFO or /dev/zero must not block or stream).
void check_msh_header(const std::string& path) {
  const std::string where = "gmsh file '" + path + "' (mesh.file): ";
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  std::istringstream lines(head);
  std::string first, format;
  while (std::getline(lines, first) && first.find_first_not_of(" \t\r") == std::string::npos) {
  }
  const auto trim = [](std::string t) {
    const size_t a = t.find_first_not_of(" \t\r"), b = t.find_last_not_of(" \t\r");
    return a == std::string::npos ? std::string() : t.substr(a, b - a + 1);
  };
  first = trim(first);
  // Gmsh chooses by the extension before the content: a .geo file is parsed as a script whatever
  // its first line says.
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const std::string script_note =
      "; a Gmsh script (.geo, or anything Gmsh does not read as a mesh) runs code (SystemCall, "
      "Printf to files) and is read only with mesh.allow_scripts = true";
  if (ext == ".geo" || ext == ".geo_unrolled")
    input_error(where + "a Gmsh script by its extension (" + ext + ")" + script_note);
  if (first != "$MeshFormat") {
    std::string shown = first.substr(0, 40);
    for (char& c : shown)
      if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) >= 127) c = '?';
    input_error(where + "not a Gmsh mesh: its first line is '" + shown +
                "', where an MSH file (version 2 or 4) starts with '$MeshFormat'" + script_note);
  }
  std::getline(lines, format);
  std::istringstream f(format);
  std::string version;
  int file_type = -1, data_size = 0;
  f >> version >> file_type >> data_size;
  // Gmsh prints the version with %g: 4.1, 2.2, and 4.0 as "4".
  const bool known_version = (version == "2" || version == "4" ||
                              ((version.rfind("2.", 0) == 0 || version.rfind("4.", 0) == 0) && version.size() > 2 &&
                               version.find_first_not_of("0123456789", 2) == std::string::npos));
  if (!f || !known_version || (file_type != 0 && file_type != 1))
    input_error(where + "unsupported MSH header '" + trim(format).substr(0, 40) +
                "': expected 'VERSION FILE-TYPE DATA-SIZE' with version 2.x or 4.x and file type 0 (ASCII) or "
                "1 (binary)" + script_note);
}

}  // namespace

Mesh read_gmsh(const std::string& path, bool allow_scripts) {
  const std::string where = "gmsh file '" + path + "': ";
  // Gmsh 4.8 does not fail on a missing file (it logs and leaves an empty model), so check first;
  // by stat, before opening: a FIFO would block in open(), and a device (/dev/zero) would stream.
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) input_error(where + "cannot open it (missing or unreadable)");
  if (std::filesystem::is_directory(path, ec)) input_error(where + "is a directory");
  if (!std::filesystem::is_regular_file(path, ec))
    input_error(where + "is not a regular file (a device, FIFO or socket)");
  if (!std::ifstream(path).good()) input_error(where + "cannot open it (missing or unreadable)");
  // Gmsh picks the format from the content, and anything that is not a mesh it runs as a script:
  // SystemCall runs commands, Printf > "file" writes files. So mesh.file must show the header of a
  // mesh (Gmsh's "MSH file format") before Gmsh sees it; scripts only on request.
  if (!allow_scripts) check_msh_header(path);
  const GmshApi& api = gmsh();  // a library that cannot be loaded is an Error of its own, not the file's
  // Gmsh merges <file>.opt after every file it opens (OpenFile.cpp, unconditionally: there is no
  // option to turn it off in 4.8), and an .opt file is a script. Without the opt-in Gmsh opens a
  // copy in a private empty folder, where nothing but the mesh exists.
  const std::optional<PrivateCopy> copy = allow_scripts ? std::nullopt : std::optional<PrivateCopy>(std::in_place, path);
  GmshSession session;
  try {
    return read_model(path, copy ? copy->file() : path);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    input_error(where + e.what());
  } catch (const GmshFailure& f) {  // asked while the session still holds Gmsh's log
    char* last_p = nullptr;
    int ierr = 0;
    api.gmshLoggerGetLastError(&last_p, &ierr);
    const std::string last = take_string(last_p);
    input_error(where + "Gmsh could not read it (" + f.call + ")" + (last.empty() ? "" : ": " + last));
  }
}

}  // namespace hemicontact
