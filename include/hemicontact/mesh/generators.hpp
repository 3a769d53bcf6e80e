#pragma once
/// @file generators.hpp  Structured meshes of rectangles (2D) and boxes (3D).

#include <hemicontact/mesh/mesh.hpp>

#include <string>

namespace hemicontact {

/// How each rectangular cell is split into triangles.
enum class Diagonal {
  RIGHT,      ///< diagonal from (x_i, y_j) to (x_{i+1}, y_{j+1})
  LEFT,       ///< diagonal from (x_{i+1}, y_j) to (x_i, y_{j+1})
  SYMMETRIC,  ///< RIGHT on the left half, LEFT (its mirror image) on the right half; mirror-symmetric
              ///< about the vertical centre line (an odd middle column uses CROSSED cells)
  CROSSED     ///< four triangles per cell around an added centre node
};

/// @return the Diagonal named "right", "left", "symmetric" or "crossed". @throws Error otherwise.
Diagonal parse_diagonal(const std::string& name);
/// @return the scene name of @p d.
const char* to_string(Diagonal d);

/// Where a graded axis puts its small cells (mesh.grading): none (uniform), near its lower end,
/// its upper end, or both ends.
enum class GradeTowards { NONE, LOW, HIGH, BOTH };

/// @return the GradeTowards named "none", "low", "high" or "both". @throws Error naming @p key otherwise.
GradeTowards parse_grade_towards(const std::string& name, const std::string& key);

/// @brief The graded 1D map φ: [0, 1] → [0, 1] of a grid coordinate t = i/n: LOW t^β, HIGH
/// 1 − (1 − t)^β, BOTH the LOW map on each half mirrored, NONE t. Cells next to a graded end have
/// size ≈ n^(−β), so a corner singularity r^α is resolved at the optimal P1 rate when β ≥ 1/α
/// in the direction across the singular line (docs/adaptivity.md, "graded meshes").
double grade_map(double t, GradeTowards towards, double beta);

/// Parameters of a structured rectangle mesh.
struct RectangleSpec {
  double x0 = 0, x1 = 1;                ///< x-interval
  double y0 = 0, y1 = 1;                ///< y-interval
  int nx = 8, ny = 8;                   ///< cells per direction
  Diagonal diagonal = Diagonal::RIGHT;  ///< cell split
  double perturb = 0;  ///< interior nodes moved by up to perturb·h (Euclidean, uniform in the disc/ball)
  unsigned seed = 1;   ///< seed of the perturbation
  GradeTowards grade_x = GradeTowards::NONE;  ///< grading of the x grid lines (mesh.grading.x)
  GradeTowards grade_y = GradeTowards::NONE;  ///< grading of the y grid lines (mesh.grading.y)
  double grading_power = 1;                   ///< β of grade_map (mesh.grading.power); 1: uniform
};

/// Build the triangulation of [x0,x1]×[y0,y1]; boundary facets are extracted (parts NONE).
/// Node (i, j) of the grid has index j·(nx+1) + i; CROSSED centre nodes follow the grid nodes.
/// @throws Error if nx, ny < 1, the interval is empty, or perturb ∉ [0, 0.5).
Mesh make_rectangle(const RectangleSpec& spec);

/// How each hexahedral cell of a box is split into 6 tetrahedra.
///
/// KUHN (Freudenthal): every cell is split along its main diagonal from the corner (x_i, y_j, z_k)
/// to (x_{i+1}, y_{j+1}, z_{k+1}); tetrahedron π (π a permutation of the axes) is the path
/// (0,0,0) → e_π1 → e_π1+e_π2 → (1,1,1) in local corner coordinates. Every square face is then cut
/// by the diagonal joining its smallest and its largest corner, the same diagonal seen from both
/// neighbouring cells, so the mesh is conforming. The xz faces carry the 2D "right" diagonal.
///
/// SYMMETRIC: KUHN reflected in x on the cells of the upper x half (i ≥ nx/2) and in y on the
/// cells of the upper y half (j ≥ ny/2), so the mesh is mirror-symmetric about x = mid and y = mid.
/// Needs even nx and ny (an odd middle column has no mirror-symmetric 6-tet split).
enum class BoxPattern { KUHN, SYMMETRIC };

/// @return the BoxPattern named "kuhn" or "symmetric". @throws Error otherwise.
BoxPattern parse_box_pattern(const std::string& name);
/// @return the scene name of @p p.
const char* to_string(BoxPattern p);

/// Parameters of a structured box mesh.
struct BoxSpec {
  double x0 = 0, x1 = 1;                  ///< x-interval
  double y0 = 0, y1 = 1;                  ///< y-interval
  double z0 = 0, z1 = 1;                  ///< z-interval
  int nx = 4, ny = 4, nz = 4;             ///< cells per direction
  BoxPattern pattern = BoxPattern::KUHN;  ///< cell split
  double perturb = 0;  ///< interior nodes moved by up to perturb·h (Euclidean, uniform in the disc/ball)
  unsigned seed = 1;   ///< seed of the perturbation
};

/// Build the tetrahedral mesh of [x0,x1]×[y0,y1]×[z0,z1] (6 positively oriented tets per cell);
/// boundary facets are extracted (parts NONE). Node (i, j, k) has index (k·(ny+1) + j)·(nx+1) + i.
/// @throws Error if a count is < 1, an interval is empty, perturb ∉ [0, 0.5), or SYMMETRIC has an
/// odd nx or ny.
Mesh make_box(const BoxSpec& spec);

}  // namespace hemicontact
