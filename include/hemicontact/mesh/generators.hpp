#pragma once
/// @file generators.hpp  Structured meshes of rectangles (2D).

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

/// Parameters of a structured rectangle mesh.
struct RectangleSpec {
  double x0 = 0, x1 = 1;               ///< x-interval
  double y0 = 0, y1 = 1;               ///< y-interval
  int nx = 8, ny = 8;                  ///< cells per direction
  Diagonal diagonal = Diagonal::RIGHT; ///< cell split
  double perturb = 0;                  ///< interior nodes moved by up to perturb·h per coordinate
  unsigned seed = 1;                   ///< seed of the perturbation
};

/// Build the triangulation of [x0,x1]×[y0,y1]; boundary facets are extracted (parts NONE).
/// Node (i, j) of the grid has index j·(nx+1) + i; CROSSED centre nodes follow the grid nodes.
/// @throws Error if nx, ny < 1, the interval is empty, or perturb ∉ [0, 0.5).
Mesh make_rectangle(const RectangleSpec& spec);

}  // namespace hemicontact
