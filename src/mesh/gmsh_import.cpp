#include <hemicontact/mesh/gmsh_import.hpp>

#include <hemicontact/core/error.hpp>

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>
#include <vector>

// Compiled only when the Gmsh API was found (CMake globs src/mesh/gmsh_*.cpp then); the fallback
// read_gmsh() of other builds lives in mesh_io.cpp.

namespace hemicontact {
namespace {

// Gmsh is a process-wide singleton: finalize() must run on every exit path, including the
// exceptions Gmsh itself throws (4.8 throws a std::string when General.AbortOnError = 2, which
// initialize() sets). User configuration files are not read so that the result does not depend
// on the machine's ~/.gmshrc.
class GmshSession {
 public:
  GmshSession() {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
  }
  ~GmshSession() {
    try {
      gmsh::finalize();
    } catch (...) {  // a destructor must not throw; nothing useful can be done here
    }
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

// Sorted node indices of a facet (third entry −1 in 2D): the key under which it is looked up.
using FacetKey = std::array<int, 3>;

FacetKey sorted_key(const int* v, int n) {
  FacetKey k{-1, -1, -1};
  std::copy(v, v + n, k.begin());
  std::sort(k.begin(), k.begin() + n);
  return k;
}

std::string element_name(int type) {
  std::string name;
  int dim = 0, order = 0, num_nodes = 0, num_primary = 0;
  std::vector<double> local;
  gmsh::model::mesh::getElementProperties(type, name, dim, order, num_nodes, local, num_primary);
  return name + " (MSH type " + std::to_string(type) + ")";
}

Mesh read_model(const std::string& path) {
  const std::string where = "gmsh file '" + path + "': ";
  gmsh::open(path);

  // Dimension: tetrahedra make it 3D, otherwise triangles make it 2D.
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> elem_tags, elem_nodes;
  gmsh::model::mesh::getElements(types, elem_tags, elem_nodes, 3, -1);
  int dim = 3;
  if (types.empty()) {
    dim = 2;
    gmsh::model::mesh::getElements(types, elem_tags, elem_nodes, 2, -1);
  }
  if (types.empty()) input_error(where + "no triangles or tetrahedra (was the mesh generated, e.g. with gmsh -2?)");
  const int cell_type = dim == 2 ? 2 : 4, facet_type = dim == 2 ? 1 : 2, nv = dim + 1;
  std::vector<std::size_t> cell_nodes;  // Gmsh node tags, nv per cell
  for (std::size_t t = 0; t < types.size(); ++t) {
    if (types[t] != cell_type)
      input_error(where + "contains " + element_name(types[t]) + " cells; only " +
                  (dim == 2 ? "3-node triangles" : "4-node tetrahedra") + " are supported");
    cell_nodes.insert(cell_nodes.end(), elem_nodes[t].begin(), elem_nodes[t].end());
  }

  // Coordinates of every node, then a renumbering of the nodes the cells use (increasing tag).
  std::vector<std::size_t> node_tags;
  std::vector<double> coord, param;
  gmsh::model::mesh::getNodes(node_tags, coord, param, -1, -1, false, false);
  std::unordered_map<std::size_t, std::size_t> row_of_tag;  // tag → position in node_tags
  for (std::size_t i = 0; i < node_tags.size(); ++i) row_of_tag[node_tags[i]] = i;
  std::vector<std::size_t> used(cell_nodes);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::unordered_map<std::size_t, int> index_of_tag;
  for (std::size_t i = 0; i < used.size(); ++i) index_of_tag[used[i]] = static_cast<int>(i);

  Mesh m;
  m.dim = dim;
  m.origin = "gmsh " + path;
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

  std::map<FacetKey, Index> boundary;
  for (Index f = 0; f < m.num_facets(); ++f) boundary[sorted_key(&m.facets(f, 0), dim)] = f;

  // Physical groups of dimension d−1 → named facet groups.
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, dim - 1);
  for (const auto& [gdim, gtag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(gdim, gtag, name);
    if (name.empty()) name = std::to_string(gtag);
    if (m.facet_groups.count(name)) input_error(where + "two physical groups are named '" + name + "'");
    std::vector<Index>& members = m.facet_groups[name];
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(gdim, gtag, entities);
    for (int ent : entities) {
      gmsh::model::mesh::getElements(types, elem_tags, elem_nodes, gdim, ent);
      for (std::size_t t = 0; t < types.size(); ++t) {
        if (types[t] != facet_type)
          input_error(where + "physical group '" + name + "' contains " + element_name(types[t]) + " elements; only " +
                      (dim == 2 ? "2-node lines" : "3-node triangles") + " are supported");
        const auto& nodes = elem_nodes[t];
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
    // A facet may be listed by two entities of one group; each facet counts once.
    std::sort(members.begin(), members.end());
    members.erase(std::unique(members.begin(), members.end()), members.end());
  }
  return m;
}

}  // namespace

Mesh read_gmsh(const std::string& path) {
  const std::string where = "gmsh file '" + path + "': ";
  // Gmsh 4.8 does not fail on a missing file (it logs and leaves an empty model), so check first.
  if (!std::ifstream(path).good()) input_error(where + "cannot open it (missing or unreadable)");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) input_error(where + "is a directory");
  GmshSession session;
  try {
    return read_model(path);
  } catch (const Error&) {
    throw;
  } catch (const std::string& s) {
    input_error(where + s);
  } catch (const std::exception& e) {
    input_error(where + e.what());
  } catch (...) {
    std::string last;
    gmsh::logger::getLastError(last);
    input_error(where + "Gmsh could not read it" + (last.empty() ? "" : ": " + last));
  }
}

}  // namespace hemicontact
