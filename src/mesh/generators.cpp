#include <hemicontact/mesh/generators.hpp>

#include <hemicontact/core/error.hpp>

#include <random>
#include <sstream>

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

Mesh make_rectangle(const RectangleSpec& s) {
  if (s.nx < 1 || s.ny < 1) input_error("mesh: nx and ny must be >= 1");
  if (!(s.x1 > s.x0) || !(s.y1 > s.y0)) input_error("mesh: empty rectangle (need x0 < x1 and y0 < y1)");
  if (!(s.perturb >= 0 && s.perturb < 0.5)) input_error("mesh.perturb must lie in [0, 0.5)");
  const int nx = s.nx, ny = s.ny;
  const double hx = (s.x1 - s.x0) / nx, hy = (s.y1 - s.y0) / ny;
  const auto grid = [nx](int i, int j) { return j * (nx + 1) + i; };

  // Which split each column uses; SYMMETRIC mirrors RIGHT into LEFT about the centre line, and an
  // odd middle column (which no two-triangle split keeps symmetric) is crossed.
  std::vector<Diagonal> column(nx, s.diagonal);
  if (s.diagonal == Diagonal::SYMMETRIC)
    for (int i = 0; i < nx; ++i)
      column[i] = (2 * i + 1 == nx) ? Diagonal::CROSSED : (2 * i + 1 < nx ? Diagonal::RIGHT : Diagonal::LEFT);
  int n_crossed = 0;
  for (int i = 0; i < nx; ++i) n_crossed += (column[i] == Diagonal::CROSSED) ? ny : 0;

  Mesh m;
  m.dim = 2;
  const Index n_grid = Index(nx + 1) * (ny + 1);
  m.points.resize(n_grid + n_crossed, 2);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      // Exact end points (x1 rather than x0 + nx·hx) so that side selection sees exact coordinates.
      m.points(grid(i, j), 0) = (i == nx) ? s.x1 : s.x0 + i * hx;
      m.points(grid(i, j), 1) = (j == ny) ? s.y1 : s.y0 + j * hy;
    }
  const Index n_cells = 2 * (Index(nx) * ny - n_crossed) + 4 * Index(n_crossed);
  m.cells.resize(n_cells, 3);
  Index c = 0, centre = n_grid;
  const auto tri = [&](int a, int b, int d) {
    m.cells(c, 0) = a;
    m.cells(c, 1) = b;
    m.cells(c, 2) = d;
    ++c;
  };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = grid(i, j), b = grid(i + 1, j), cc = grid(i + 1, j + 1), d = grid(i, j + 1);
      switch (column[i]) {
        case Diagonal::RIGHT: tri(a, b, cc); tri(a, cc, d); break;
        case Diagonal::LEFT: tri(a, b, d); tri(b, cc, d); break;
        default: {
          m.points(centre, 0) = s.x0 + (i + 0.5) * hx;
          m.points(centre, 1) = s.y0 + (j + 0.5) * hy;
          const int e = static_cast<int>(centre++);
          tri(a, b, e); tri(b, cc, e); tri(cc, d, e); tri(d, a, e);
        }
      }
    }
  if (s.perturb > 0) {
    // Interior grid nodes only, so the boundary (and the parts on it) stay exactly where they are.
    std::mt19937 rng(s.seed);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (int j = 1; j < ny; ++j)
      for (int i = 1; i < nx; ++i) {
        m.points(grid(i, j), 0) += s.perturb * hx * U(rng);
        m.points(grid(i, j), 1) += s.perturb * hy * U(rng);
      }
  }
  std::ostringstream os;
  os << "rectangle [" << s.x0 << "," << s.x1 << "]x[" << s.y0 << "," << s.y1 << "] " << nx << "x" << ny
     << " " << to_string(s.diagonal);
  if (s.perturb > 0) os << " perturbed " << s.perturb;
  m.origin = os.str();
  extract_boundary_facets(m);
  return m;
}

}  // namespace hemicontact
