#include <hemicontact/mesh/boundary.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/mesh/slabs.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hemicontact {
namespace {

// The bounding-box face a side name denotes, and the coordinate `from`/`to` measure along it.
// 2D: left/right are x = min/max and bottom/top y = min/max; the coordinate along a side is the
// other one. 3D: left/right x, front/back y, bottom/top z; along the lateral faces the coordinate
// is the vertical z (so "the upper half" of a side is [0.5, 1) on the unit cube), along bottom/top x.
struct SideAxes {
  int axis;     // the coordinate that is constant on the side
  bool at_max;  // the side is at its maximum
  int along;    // the coordinate compared with [from, to)
};

SideAxes side_axes(const BoundarySelector& s, int dim) {
  const bool d3 = dim == 3;
  if (s.side == "left") return {0, false, d3 ? 2 : 1};
  if (s.side == "right") return {0, true, d3 ? 2 : 1};
  if (s.side == "bottom") return {d3 ? 2 : 1, false, 0};
  if (s.side == "top") return {d3 ? 2 : 1, true, 0};
  if (s.side == "front" || s.side == "back") {
    if (!d3)
      input_error(s.context + ".side: '" + s.side +
                  "' (y = min/max) exists on 3D meshes only; in 2D use left, right, bottom, top");
    return {1, s.side == "back", 2};
  }
  input_error(s.context + ".side: unknown side '" + s.side + "' (expected left, right, bottom, top" +
              (d3 ? ", front, back)" : ")"));
}

// Does facet f lie on the bounding-box side, with its midpoint in [from, to)?
bool selects(const Mesh& m, Index f, const BoundarySelector& s, const SideAxes& a, const RowMat& lo, const RowMat& hi,
             double tol) {
  const double target = a.at_max ? hi(0, a.axis) : lo(0, a.axis);
  for (int v = 0; v < m.dim; ++v)
    if (std::abs(m.points(m.facets(f, v), a.axis) - target) > tol) return false;
  double mid = 0;
  for (int v = 0; v < m.dim; ++v) mid += m.points(m.facets(f, v), a.along);
  mid /= m.dim;
  return mid >= s.from && mid < s.to;
}

// The bounding box the sides refer to: the mesh's own, or the whole mesh's for a piece of it
// (assign_boundary_in_box); then an empty selection is allowed (the caller counts over the pieces).
struct SideBox {
  const RowMat* lo = nullptr;
  const RowMat* hi = nullptr;
};

// The boundary facets selector @p s matches (never empty on a whole mesh: that is an error naming it).
std::vector<Index> select_facets(const Mesh& m, const BoundarySelector& s, const SideBox& box = {}) {
  const RowMat lo = box.lo ? *box.lo : RowMat(m.points.colwise().minCoeff());
  const RowMat hi = box.hi ? *box.hi : RowMat(m.points.colwise().maxCoeff());
  const double tol = 1e-9 * (hi - lo).maxCoeff();
  if (s.side.empty() == s.physical.empty()) input_error(s.context + ": give exactly one of 'side' and 'physical'");
  if (s.from >= s.to) input_error(s.context + ": empty interval [from, to)");
  std::vector<Index> chosen;
  if (!s.side.empty()) {
    const SideAxes axes = side_axes(s, m.dim);
    for (Index f = 0; f < m.num_facets(); ++f)
      if (selects(m, f, s, axes, lo, hi, tol)) chosen.push_back(f);
  } else {
    // The interval is measured along a side: on a group it cannot restrict anything, and ignoring
    // it would select more than asked for (the scene checker refuses it first, naming the key).
    if (std::isfinite(s.from) || std::isfinite(s.to))
      input_error(s.context + ": an interval [from, to) restricts a 'side' selector only, not 'physical' '" +
                  s.physical + "'");
    auto it = m.facet_groups.find(s.physical);
    if (it == m.facet_groups.end()) {
      std::string names;
      for (const auto& [k, v] : m.facet_groups) names += (names.empty() ? "" : ", ") + k;
      input_error(s.context + ".physical: the mesh has no facet group '" + s.physical +
                  "' (groups: " + (names.empty() ? "none" : names) + ")");
    }
    chosen = it->second;
  }
  if (chosen.empty() && !box.lo) input_error(s.context + " selects no boundary facet");
  return chosen;
}

void assign(Mesh& m, const std::vector<BoundarySelector>& sel, Part part, std::vector<std::string>& owner,
            const SideBox& box = {}, std::vector<long>* counts = nullptr) {
  for (const auto& s : sel) {
    const std::vector<Index> chosen = select_facets(m, s, box);
    if (counts) counts->push_back(static_cast<long>(chosen.size()));
    int load = -1;
    if (part == Part::GAMMA2) {
      if (s.traction.size() != m.dim)
        input_error(s.context + ".traction: expected " + std::to_string(m.dim) + " components");
      load = static_cast<int>(m.tractions.size());
      m.tractions.push_back(s.traction);
    }
    for (Index f : chosen) {
      if (!owner[f].empty()) {
        std::ostringstream os;
        os << s.context << " and " << owner[f] << " both select the boundary facet (" << m.facets(f, 0);
        for (int a = 1; a < m.dim; ++a) os << ", " << m.facets(f, a);
        os << ")";
        input_error(os.str());
      }
      owner[f] = s.context;
      m.facet_part[f] = part;
      m.facet_load[f] = load;
    }
  }
}

}  // namespace

namespace {

// The parts and rollers of assign_boundary, with the sides of @p box; @p counts (when given) gets
// each selector's number of facets.
void assign_parts(Mesh& mesh, const BoundarySpec& spec, const SideBox& box, std::vector<long>* counts) {
  std::vector<std::string> owner(mesh.num_facets());
  mesh.tractions.clear();
  assign(mesh, spec.gamma1, Part::GAMMA1, owner, box, counts);
  assign(mesh, spec.gamma2, Part::GAMMA2, owner, box, counts);
  assign(mesh, spec.gamma3, Part::GAMMA3, owner, box, counts);
  mesh.node_fixed.clear();
  for (const auto& s : spec.rollers) {
    if (s.components.empty()) input_error(s.context + ".components: name at least one component to hold at zero");
    unsigned char mask = 0;
    for (int c : s.components) {
      if (c < 0 || c >= mesh.dim)
        input_error(s.context + ".components: component " + std::string(1, "xyz"[std::clamp(c, 0, 2)]) +
                    " does not exist on a " + std::to_string(mesh.dim) + "D mesh");
      mask |= static_cast<unsigned char>(1u << c);
    }
    if (mesh.node_fixed.empty()) mesh.node_fixed.assign(mesh.num_nodes(), 0);
    const std::vector<Index> chosen = select_facets(mesh, s, box);
    if (counts) counts->push_back(static_cast<long>(chosen.size()));
    for (Index f : chosen)
      for (int a = 0; a < mesh.dim; ++a) mesh.node_fixed[mesh.facets(f, a)] |= mask;
  }
}

}  // namespace

std::vector<long> assign_boundary_in_box(Mesh& mesh, const BoundarySpec& spec, const RowMat& lo, const RowMat& hi) {
  std::vector<long> counts;
  assign_parts(mesh, spec, SideBox{&lo, &hi}, &counts);
  return counts;
}

void assign_boundary(Mesh& mesh, const BoundarySpec& spec) {
  assign_parts(mesh, spec, SideBox{}, nullptr);
  bool any_gamma1 = false;
  for (Part p : mesh.facet_part) any_gamma1 |= (p == Part::GAMMA1);
  if (!any_gamma1)
    input_error("boundary: no Γ1 (clamped) facet: the problem is not coercive (the paper needs meas(Γ1) > 0)");
}

std::vector<bool> clamped_nodes(const Mesh& mesh) {
  std::vector<bool> clamped(mesh.num_nodes(), false);
  for (Index f = 0; f < mesh.num_facets(); ++f)
    if (mesh.facet_part[f] == Part::GAMMA1)
      for (int a = 0; a < mesh.dim; ++a) clamped[mesh.facets(f, a)] = true;
  return clamped;
}

}  // namespace hemicontact
