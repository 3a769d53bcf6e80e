#include <hemicontact/mesh/generators.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/mesh/slabs.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <sstream>
#include <utility>

namespace hemicontact {

Diagonal parse_diagonal(const std::string& name) {
  if (name == "right") return Diagonal::RIGHT;
  if (name == "left") return Diagonal::LEFT;
  if (name == "symmetric") return Diagonal::SYMMETRIC;
  if (name == "crossed") return Diagonal::CROSSED;
  input_error("mesh.diagonal: unknown value '" + name + "' (expected right, left, symmetric or crossed)");
}

const char* to_string(Diagonal d) {
  switch (d) {
    case Diagonal::RIGHT: return "right";
    case Diagonal::LEFT: return "left";
    case Diagonal::SYMMETRIC: return "symmetric";
    default: return "crossed";
  }
}

GradeTowards parse_grade_towards(const std::string& name, const std::string& key) {
  if (name == "none") return GradeTowards::NONE;
  if (name == "low") return GradeTowards::LOW;
  if (name == "high") return GradeTowards::HIGH;
  if (name == "both") return GradeTowards::BOTH;
  input_error(key + ": unknown grading '" + name + "' (expected none, low, high or both)");
}

double grade_map(double t, GradeTowards towards, double beta) {
  switch (towards) {
    case GradeTowards::LOW: return std::pow(t, beta);
    case GradeTowards::HIGH: return 1 - std::pow(1 - t, beta);
    case GradeTowards::BOTH: return t <= 0.5 ? 0.5 * std::pow(2 * t, beta) : 1 - 0.5 * std::pow(2 * (1 - t), beta);
    default: return t;
  }
}

namespace {

// The graded grid lines' positions in [0, 1] (grade_map).
double rect_grade_x(const RectangleSpec& s, int i) {
  return grade_map(static_cast<double>(i) / s.nx, s.grade_x, s.grading_power);
}
double rect_grade_y(const RectangleSpec& s, int j) {
  return grade_map(static_cast<double>(j) / s.ny, s.grade_y, s.grading_power);
}

void check_graded_cells(const RectangleSpec& s) {
  const int nx = s.nx, ny = s.ny;
  const auto gx = [&](int i) { return rect_grade_x(s, i); };
  const auto gy = [&](int j) { return rect_grade_y(s, j); };
  // The smallest cell (the two smallest spacings) against the largest spacing: below check_cells'
  // round-off floor (1e-12 h²; 1e-10 here, a margin) the power made it degenerate, and the message
  // should name the power, not a cell (power 50, or inf, once named a cell).
  const auto spacings = [](int n, const auto& g, double len) {
    double lo = INF, hi = 0;
    for (int i = 0; i < n; ++i) lo = std::min(lo, len * (g(i + 1) - g(i))), hi = std::max(hi, len * (g(i + 1) - g(i)));
    return std::pair<double, double>(lo, hi);
  };
  const auto [dx_min, dx_max] = spacings(nx, gx, s.x1 - s.x0);
  const auto [dy_min, dy_max] = spacings(ny, gy, s.y1 - s.y0);
  const double h = std::max(dx_max, dy_max);
  if (!(0.5 * dx_min * dy_min >= 1e-10 * h * h)) {
    std::ostringstream os;
    os << "mesh.grading.power = " << s.grading_power << " with " << nx << " x " << ny
       << " cells: the smallest graded cell's area is " << 0.5 * dx_min * dy_min / (h * h)
       << " of the largest spacing squared, below round-off (a degenerate cell); lower mesh.grading.power "
          "(or mesh.n)";
    input_error(os.str());
  }
}

std::vector<Diagonal> column_splits(const RectangleSpec& s) {
  const int nx = s.nx;
  // Which split each column uses; SYMMETRIC mirrors RIGHT into LEFT about the centre line, and an
  // odd middle column (which no two-triangle split keeps symmetric) is crossed.
  std::vector<Diagonal> column(nx, s.diagonal);
  if (s.diagonal == Diagonal::SYMMETRIC)
    for (int i = 0; i < nx; ++i)
      column[i] = (2 * i + 1 == nx) ? Diagonal::CROSSED : (2 * i + 1 < nx ? Diagonal::RIGHT : Diagonal::LEFT);
  return column;
}

void perturb_interior(const RectangleSpec& s, double hx, double hy, Mesh& m) {
  const int nx = s.nx, ny = s.ny;
  const auto grid = [nx](int i, int j) { return j * (nx + 1) + i; };
  // Interior grid nodes only, so the boundary (and the parts on it) stay exactly where they are.
  // Each node moves by at most perturb·h (Euclidean, in units of the cell sides; uniform in the
  // disc, drawn by rejection from the square), so "moved by up to 30 % of h" means what it says.
  std::mt19937 rng(s.seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int j = 1; j < ny; ++j)
    for (int i = 1; i < nx; ++i) {
      double a, b;
      do {
        a = U(rng);
        b = U(rng);
      } while (a * a + b * b > 1);
      m.points(grid(i, j), 0) += s.perturb * hx * a;
      m.points(grid(i, j), 1) += s.perturb * hy * b;
    }
}

// The nodes and cells of the rectangle's cell columns i0 <= i < i1 (the whole rectangle: 0, nx);
// grid node (i, j) gets the index j·(i1 − i0 + 1) + i − i0 and the centre nodes of crossed cells
// follow, so the whole rectangle keeps the numbering make_rectangle documents. Not perturbed.
Mesh rectangle_cells(const RectangleSpec& s, int i0, int i1) {
  const int nxl = i1 - i0, ny = s.ny;
  const auto gx = [&](int i) { return rect_grade_x(s, i); };
  const auto gy = [&](int j) { return rect_grade_y(s, j); };
  const auto grid = [nxl, i0](int i, int j) { return j * (nxl + 1) + i - i0; };
  const std::vector<Diagonal> column = column_splits(s);
  int n_crossed = 0;
  for (int i = i0; i < i1; ++i) n_crossed += (column[i] == Diagonal::CROSSED) ? ny : 0;

  Mesh m;
  m.dim = 2;
  const Index n_grid = Index(nxl + 1) * (ny + 1);
  m.points.resize(n_grid + n_crossed, 2);
  for (int j = 0; j <= ny; ++j)
    for (int i = i0; i <= i1; ++i) {
      // Exact end points (x1 rather than x0 + nx·hx) so that side selection sees exact coordinates.
      m.points(grid(i, j), 0) = (i == s.nx) ? s.x1 : s.x0 + (s.x1 - s.x0) * gx(i);
      m.points(grid(i, j), 1) = (j == ny) ? s.y1 : s.y0 + (s.y1 - s.y0) * gy(j);
    }
  const Index n_cells = 2 * (Index(nxl) * ny - n_crossed) + 4 * Index(n_crossed);
  m.cells.resize(n_cells, 3);
  Index c = 0, centre = n_grid;
  const auto tri = [&](int a, int b, int d) {
    m.cells(c, 0) = a;
    m.cells(c, 1) = b;
    m.cells(c, 2) = d;
    ++c;
  };
  for (int j = 0; j < ny; ++j)
    for (int i = i0; i < i1; ++i) {
      const int a = grid(i, j), b = grid(i + 1, j), cc = grid(i + 1, j + 1), d = grid(i, j + 1);
      switch (column[i]) {
        case Diagonal::RIGHT:
          tri(a, b, cc);
          tri(a, cc, d);
          break;
        case Diagonal::LEFT:
          tri(a, b, d);
          tri(b, cc, d);
          break;
        default: {
          m.points(centre, 0) = s.x0 + (s.x1 - s.x0) * 0.5 * (gx(i) + gx(i + 1));
          m.points(centre, 1) = s.y0 + (s.y1 - s.y0) * 0.5 * (gy(j) + gy(j + 1));
          const int e = static_cast<int>(centre++);
          tri(a, b, e);
          tri(b, cc, e);
          tri(cc, d, e);
          tri(d, a, e);
        }
      }
    }
  return m;
}

std::string rectangle_origin(const RectangleSpec& s, bool graded) {
  std::ostringstream os;
  os << "rectangle [" << s.x0 << "," << s.x1 << "]x[" << s.y0 << "," << s.y1 << "] " << s.nx << "x" << s.ny << " "
     << to_string(s.diagonal);
  if (s.perturb > 0) os << " perturbed " << s.perturb;
  if (graded) os << " graded " << s.grading_power;
  return os.str();
}

bool check_rectangle(const RectangleSpec& s) {
  if (s.nx < 1 || s.ny < 1) input_error("mesh: nx and ny must be >= 1");
  if (!(s.x1 > s.x0) || !(s.y1 > s.y0)) input_error("mesh: empty rectangle (need x0 < x1 and y0 < y1)");
  if (!(s.perturb >= 0 && s.perturb < 0.5)) input_error("mesh.perturb must lie in [0, 0.5)");
  if (!(s.grading_power >= 1)) input_error("mesh.grading.power must be >= 1");
  const bool graded = s.grading_power != 1 && (s.grade_x != GradeTowards::NONE || s.grade_y != GradeTowards::NONE);
  // A perturbation is sized by the uniform h: on a graded mesh it would invert the small cells.
  if (graded && s.perturb > 0) input_error("mesh.grading and mesh.perturb cannot be combined");
  if (graded) check_graded_cells(s);
  return graded;
}

}  // namespace

Mesh make_rectangle(const RectangleSpec& s) {
  const bool graded = check_rectangle(s);
  Mesh m = rectangle_cells(s, 0, s.nx);
  const double hx = (s.x1 - s.x0) / s.nx, hy = (s.y1 - s.y0) / s.ny;
  if (s.perturb > 0) perturb_interior(s, hx, hy, m);
  m.origin = rectangle_origin(s, graded);
  extract_boundary_facets(m);
  return m;
}

Mesh make_rectangle_slab(const RectangleSpec& s, int i0, int i1) {
  const bool graded = check_rectangle(s);
  if (s.perturb > 0) input_error("mesh.perturb: a rectangle made in slabs is not perturbed (its draws run over the whole mesh)");
  if (!(0 <= i0 && i0 < i1 && i1 <= s.nx)) throw Error("make_rectangle_slab: cell columns out of range", EXIT_INTERNAL);
  for (Diagonal c : column_splits(s))
    if (c == Diagonal::CROSSED)
      input_error("mesh.diagonal: a rectangle made in slabs has no crossed cells (their centre nodes are not shared)");
  Mesh m = rectangle_cells(s, i0, i1);
  m.origin = rectangle_origin(s, graded);
  extract_boundary_facets(m);
  return m;
}

BoxPattern parse_box_pattern(const std::string& name) {
  if (name == "kuhn") return BoxPattern::KUHN;
  if (name == "symmetric") return BoxPattern::SYMMETRIC;
  input_error("mesh.pattern: unknown value '" + name + "' (expected kuhn or symmetric)");
}

const char* to_string(BoxPattern p) { return p == BoxPattern::KUHN ? "kuhn" : "symmetric"; }

namespace {

void check_box(const BoxSpec& s) {
  if (s.nx < 1 || s.ny < 1 || s.nz < 1) input_error("mesh: nx, ny and nz must be >= 1");
  if (!(s.x1 > s.x0) || !(s.y1 > s.y0) || !(s.z1 > s.z0))
    input_error("mesh: empty box (need x0 < x1, y0 < y1 and z0 < z1)");
  if (!(s.perturb >= 0 && s.perturb < 0.5)) input_error("mesh.perturb must lie in [0, 0.5)");
  if (s.pattern == BoxPattern::SYMMETRIC && (s.nx % 2 || s.ny % 2))
    input_error("mesh.pattern: 'symmetric' needs even nx and ny (got nx = " + std::to_string(s.nx) +
                ", ny = " + std::to_string(s.ny) + "); an odd middle column has no mirror-symmetric split");
}

// The nodes and cells of the box's cell layers j0 <= j < j1 along y (the whole box: 0, ny); node
// (i, j, k) gets the index (k·(j1 − j0 + 1) + j − j0)·(nx + 1) + i, so the whole box keeps the
// numbering make_box documents. Cells are split by their global (i, j), as in the whole box.
// The cells of the box's columns [i0, i1) × [j0, j1) (all z layers) and their nodes, numbered
// (k·(j1 − j0 + 1) + j − j0)·(i1 − i0 + 1) + i − i0: make_box's numbering for the whole range.
Mesh box_cells(const BoxSpec& s, int i0, int i1, int j0, int j1) {
  const int nx = s.nx, ny = s.ny, nz = s.nz, nxl = i1 - i0, nyl = j1 - j0;
  const double hx = (s.x1 - s.x0) / nx, hy = (s.y1 - s.y0) / ny, hz = (s.z1 - s.z0) / nz;
  const auto grid = [nxl, nyl, i0, j0](int i, int j, int k) {
    return (k * (nyl + 1) + j - j0) * (nxl + 1) + i - i0;
  };

  Mesh m;
  m.dim = 3;
  m.points.resize(Index(nxl + 1) * (nyl + 1) * (nz + 1), 3);
  for (int k = 0; k <= nz; ++k)
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const int v = grid(i, j, k);
        // Exact end points so that side selection sees exact coordinates.
        m.points(v, 0) = (i == nx) ? s.x1 : s.x0 + i * hx;
        m.points(v, 1) = (j == ny) ? s.y1 : s.y0 + j * hy;
        m.points(v, 2) = (k == nz) ? s.z1 : s.z0 + k * hz;
      }

  // The six Kuhn tetrahedra in local corner bits (bit 0 = x, 1 = y, 2 = z): for the axis order
  // (a, b, c) the path 0 → e_a → e_a+e_b → 7. det[e_a, e_a+e_b, e_a+e_b+e_c] = det[e_a, e_b, e_c]
  // is the sign of the permutation, so the odd ones swap their two middle vertices.
  static const int perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  std::array<std::array<int, 4>, 6> kuhn{};
  for (int t = 0; t < 6; ++t) {
    const int a = 1 << perms[t][0], b = a | (1 << perms[t][1]);
    kuhn[t] = t < 3 ? std::array<int, 4>{0, a, b, 7} : std::array<int, 4>{0, b, a, 7};
  }

  m.cells.resize(Index(nxl) * nyl * nz * 6, 4);
  Index c = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = j0; j < j1; ++j)
      for (int i = i0; i < i1; ++i) {
        // SYMMETRIC: the mirror image of the Kuhn split in the upper halves. Reflecting x maps local
        // bit x to 1 − x (flip = 1), and likewise y. Conformity: faces inside one half see the same
        // (reflected) split from both cells, so they match as in KUHN. A face on the mirror plane
        // x = mid is a yz face; a reflection in x leaves its diagonal (smallest to largest corner in
        // y, z) unchanged, so both sides cut it the same way; likewise for y = mid. A reflection is
        // orientation-reversing, so one reflection swaps two vertices to keep the volume positive.
        const bool fx = s.pattern == BoxPattern::SYMMETRIC && 2 * i >= nx;
        const bool fy = s.pattern == BoxPattern::SYMMETRIC && 2 * j >= ny;
        const int flip = (fx ? 1 : 0) | (fy ? 2 : 0);
        const auto corner = [&](int bits) {
          const int l = bits ^ flip;
          return grid(i + (l & 1), j + ((l >> 1) & 1), k + ((l >> 2) & 1));
        };
        for (const auto& t : kuhn) {
          std::array<int, 4> v{corner(t[0]), corner(t[1]), corner(t[2]), corner(t[3])};
          if (fx != fy) std::swap(v[1], v[2]);
          for (int a = 0; a < 4; ++a) m.cells(c, a) = v[a];
          ++c;
        }
      }
  return m;
}

std::string box_origin(const BoxSpec& s) {
  std::ostringstream os;
  os << "box [" << s.x0 << "," << s.x1 << "]x[" << s.y0 << "," << s.y1 << "]x[" << s.z0 << "," << s.z1 << "] " << s.nx
     << "x" << s.ny << "x" << s.nz << " " << to_string(s.pattern);
  if (s.perturb > 0) os << " perturbed " << s.perturb;
  return os.str();
}

}  // namespace

Mesh make_box(const BoxSpec& s) {
  check_box(s);
  Mesh m = box_cells(s, 0, s.nx, 0, s.ny);
  const int nx = s.nx, ny = s.ny, nz = s.nz;
  const double hx = (s.x1 - s.x0) / nx, hy = (s.y1 - s.y0) / ny, hz = (s.z1 - s.z0) / nz;
  const auto grid = [nx, ny](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  if (s.perturb > 0) {
    // Interior nodes only, so the boundary (and the parts on it) stay exactly where they are.
    // At most perturb·h (Euclidean, in cell-side units; uniform in the ball, by rejection).
    std::mt19937 rng(s.seed);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (int k = 1; k < nz; ++k)
      for (int j = 1; j < ny; ++j)
        for (int i = 1; i < nx; ++i) {
          const int v = grid(i, j, k);
          double a, b, c;
          do {
            a = U(rng);
            b = U(rng);
            c = U(rng);
          } while (a * a + b * b + c * c > 1);
          m.points(v, 0) += s.perturb * hx * a;
          m.points(v, 1) += s.perturb * hy * b;
          m.points(v, 2) += s.perturb * hz * c;
        }
  }
  m.origin = box_origin(s);
  extract_boundary_facets(m);
  return m;
}

Mesh make_box_slab(const BoxSpec& s, int j0, int j1) {
  check_box(s);
  if (s.perturb > 0) input_error("mesh.perturb: a box made in slabs is not perturbed (its draws run over the whole box)");
  if (!(0 <= j0 && j0 < j1 && j1 <= s.ny)) throw Error("make_box_slab: cell layers out of range", EXIT_INTERNAL);
  Mesh m = box_cells(s, 0, s.nx, j0, j1);
  m.origin = box_origin(s);
  extract_boundary_facets(m);
  return m;
}

Mesh make_box_block(const BoxSpec& s, int i0, int i1, int j0, int j1) {
  check_box(s);
  if (s.perturb > 0) input_error("mesh.perturb: a box made in blocks is not perturbed (its draws run over the whole box)");
  if (!(0 <= i0 && i0 < i1 && i1 <= s.nx && 0 <= j0 && j0 < j1 && j1 <= s.ny))
    throw Error("make_box_block: cell columns out of range", EXIT_INTERNAL);
  Mesh m = box_cells(s, i0, i1, j0, j1);
  m.origin = box_origin(s);
  extract_boundary_facets(m);
  return m;
}

}  // namespace hemicontact
