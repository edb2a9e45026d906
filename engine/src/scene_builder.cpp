#include "scene_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernel.hpp"
#include "pore_contact.hpp"
#include "splitmix64.hpp"
#include "void_layout.hpp"

namespace compaction {

namespace {

void build_grid(const SceneParams& p, Grid& g) {
  const int cells_per_unit = p.grid_cells_per_unit();
  g.dx = p.grid_spacing();
  g.inv_dx = 1.0 / g.dx;
  g.periodic_x = p.geometry == Geometry::pseudo1d;
  g.cells_x = p.cols() * cells_per_unit;
  g.cells_y = p.n_rows * cells_per_unit;
  // Ghost nodes: a particle at distance >= 0 from an edge reaches one node beyond it, and the
  // stability checks stop a run before any particle gets further than 1.4 cells out.
  g.gy = 2;
  g.ny = g.cells_y + g.gy + 4;
  if (g.periodic_x) {
    g.gx = 0;
    g.nx = g.cells_x;
  } else {
    g.gx = 2;
    g.nx = g.cells_x + 2 * g.gx + 1;
  }
  // Stencil columns base + k, base in [-1, nx - 1] (periodic) or [0, nx - 3]: wrapped once here
  // so that the transfer loops never compute a modulo.
  g.col.resize(g.nx + 3);
  for (int k = 0; k < g.nx + 3; ++k) {
    g.col[k] = g.periodic_x ? ((k - 1) % g.nx + g.nx) % g.nx : std::min(k - 1, g.nx - 1);
  }
  const std::size_t nodes = static_cast<std::size_t>(g.nx) * g.ny;
  g.arrays.nodes.assign(nodes, Node{0, 0, 0, 0});
  if (p.transfer == Transfer::pic_flip) {
    g.arrays.mx.assign(nodes, 0.0);
    g.arrays.my.assign(nodes, 0.0);
  }
  if (resolved_pore_contact(p) == PoreContact::split_fields) {
    g.field2 = nodes;
    g.arrays.nodes.assign(2 * nodes, Node{0, 0, 0, 0});
    g.arrays.windows.assign(nodes, 0);
    g.split.node.assign(nodes, 0);
    g.split.reach.assign(nodes, 0);
    g.split.thread_nodes.resize(p.threads);
    for (auto& list : g.split.thread_nodes) list.reserve(nodes);
    g.split.nodes.reserve(nodes);
    g.split.normal.assign(nodes, NodeNormal{0, 0});
  }
  g.scratch.assign(static_cast<std::size_t>(p.threads - 1), g.arrays);
  for (NodeArrays& a : g.scratch) a.nodes.resize(nodes);  // threads scatter the first field only
  g.scatter_rows.resize(p.threads, g.ny);
}

// The unit normal of the pore face nearest to (px, py) in unit cell (cx, cy), pointing from the
// pore into the solid (pore_contact.hpp); zero without pores. The voids of the cell and its
// eight neighbours are searched (pseudo1d: its own, shifted by the width), the first nearest
// wins.
void face_normal(const VoidLayout& voids, int per_unit, double spacing, double width,
                 bool periodic, int cx, int cy, double px, double py, double& nx, double& ny) {
  double best = std::numeric_limits<double>::infinity();
  nx = ny = 0.0;
  for (int dy = -1; dy <= 1; ++dy) {
    const int vy = cy + dy;
    if (vy < 0 || vy >= voids.rows) continue;
    for (int dx = -1; dx <= 1; ++dx) {
      int vx = cx + dx;
      double shift = 0.0;
      if (periodic) {
        shift = vx < 0 ? -width : (vx >= voids.cols ? width : 0.0);
        vx = (vx + voids.cols) % voids.cols;
      } else if (vx < 0 || vx >= voids.cols) {
        continue;
      }
      const Void& v = voids.at(vx, vy);
      if (v.empty()) continue;
      const double x0 = (vx * per_unit + v.x0) * spacing + shift;
      const double x1 = (vx * per_unit + v.x1) * spacing + shift;
      const double y0 = (vy * per_unit + v.y0) * spacing, y1 = (vy * per_unit + v.y1) * spacing;
      const double ox = px - std::clamp(px, x0, x1), oy = py - std::clamp(py, y0, y1);
      const double d = std::hypot(ox, oy);
      if (d < best && d > 0.0) best = d, nx = ox / d, ny = oy / d;
    }
  }
}

// The constants of the scene that the stages read (strut geometry: place_particles).
Setup make_setup(const SceneParams& p) {
  Setup su;
  su.material.lambda = p.lame_lambda();
  su.material.mu = p.lame_mu();
  su.material.d_yield = p.q_y / (std::sqrt(3.0) * su.material.mu);
  su.V = p.plate_speed();
  su.h0 = p.h0;
  su.width = p.width();
  su.c_p = p.p_wave_speed();
  su.transfer = p.transfer;
  su.flip_ratio = p.flip_ratio;
  su.gradient = p.gradient;
  su.contact = p.contact;
  su.split_fields = resolved_pore_contact(p) == PoreContact::split_fields;
  su.side_walls = p.geometry == Geometry::full2d;
  return su;
}

// The particles of the perforated specimen, at rest and unstrained; sets the strut count and
// thickness of `su`.
Particles place_particles(const SceneParams& p, const Grid& g, Setup& su) {
  const int per_unit = p.grid_cells_per_unit() * p.particles_per_cell;  // particles per unit cell side
  const double spacing = g.dx / p.particles_per_cell;
  const VoidLayout voids = void_layout(p, per_unit);
  const int strut_cols = p.geometry == Geometry::pseudo1d ? 1 : p.cols() + 1;
  su.n_struts = strut_cols * p.n_rows;
  // The regular structure's strut (a random one's struts differ from it; the deflection
  // diagnostic normalises by this nominal value).
  su.strut_thickness = (per_unit - regular_void_side(p, per_unit)) * spacing;

  Particles P;
  P.vol0 = spacing * spacing;
  P.mass = p.rho * P.vol0;
  SplitMix64 rng{p.seed};
  const int npx = p.cols() * per_unit, npy = p.n_rows * per_unit;
  for (int j = 0; j < npy; ++j) {
    const int cy = j / per_unit, ly = j % per_unit;  // cell row, particle row within it
    for (int i = 0; i < npx; ++i) {
      const int cx = i / per_unit, lx = i % per_unit;
      const Void& v = voids.at(cx, cy);
      const bool hole_row = !v.empty() && ly >= v.y0 && ly < v.y1;
      const bool hole_col = !v.empty() && lx >= v.x0 && lx < v.x1;
      if (hole_row && hole_col) continue;
      double px = (i + 0.5) * spacing, py = (j + 0.5) * spacing;
      if (p.perturbation > 0.0) {
        px += (2.0 * rng.uniform() - 1.0) * p.perturbation * spacing;
        py += (2.0 * rng.uniform() - 1.0) * p.perturbation * spacing;
        if (g.periodic_x) px = px >= su.width ? px - su.width : (px < 0.0 ? px + su.width : px);
      }
      P.x.push_back(px);
      P.y.push_back(py);
      if (su.split_fields) {
        double nx, ny;
        face_normal(voids, per_unit, spacing, su.width, g.periodic_x, cx, cy, px, py, nx, ny);
        P.nx.push_back(nx);
        P.ny.push_back(ny);
      }
      P.x0.push_back(px);
      // A vertical strut spans the rows of its cell's hole, between two holes of a row.
      if (hole_row) {
        // The strut a column belongs to: the cell edge it is nearest (pseudo1d: the only one).
        int edge = cx + (lx >= v.x1 ? 1 : 0);
        if (p.geometry == Geometry::pseudo1d) edge = 0;
        P.strut.push_back(cy * strut_cols + edge);
        const double from_mid = std::abs(ly + 0.5 - 0.5 * (v.y0 + v.y1));
        P.strut_mid.push_back(from_mid < 0.25 * (v.y1 - v.y0) ? 1 : 0);
      } else {
        P.strut.push_back(-1);
        P.strut_mid.push_back(0);
      }
    }
  }
  P.n = P.x.size();
  P.vx.assign(P.n, 0.0);
  P.vy.assign(P.n, 0.0);
  P.C.assign(P.n, Mat2{0, 0, 0, 0});
  P.Fe.assign(P.n, Mat2{1, 0, 0, 1});
  P.tau.assign(P.n, Sym2{0, 0, 0});
  P.dep.assign(P.n, 0.0);
  P.ep.assign(P.n, 0.0);
  if (su.split_fields) P.field_bits.assign(P.n, 0);
  return P;
}

// The particles' extent, as a step would have measured it (the first step's rows read it).
StepMeasure initial_measure(const Particles& P) {
  StepMeasure m;
  m.y_min = m.x_min = 1e300;
  m.y_max = m.x_max = -1e300;
  for (std::size_t k = 0; k < P.n; ++k) {
    m.y_min = std::min(m.y_min, P.y[k]), m.y_max = std::max(m.y_max, P.y[k]);
    m.x_min = std::min(m.x_min, P.x[k]), m.x_max = std::max(m.x_max, P.x[k]);
  }
  return m;
}

}  // namespace

State build_scene(const SceneParams& p) {
  State s;
  build_grid(p, s.grid);
  s.setup = make_setup(p);
  s.particles = place_particles(p, s.grid, s.setup);
  if (s.setup.split_fields) {
    s.grid.split.particles.reserve(s.particles.n);
    s.grid.split.thread_particles.resize(p.threads);
    for (auto& list : s.grid.split.thread_particles) list.reserve(s.particles.n);
    s.grid.split.first_node.assign(s.particles.n, 0);
  }
  const Grid& g = s.grid;
  s.setup.scale = s.particles.vol0 * kernel::kInverseInertia * g.inv_dx * g.inv_dx;  // V0 D^-1, MLS
  s.setup.vol0 = s.particles.vol0;
  // A full node holds rho dx^2: the particles' masses times their weights sum to it.
  s.setup.merge_mass = pore_contact::kMergeCoverage * p.rho * g.dx * g.dx;
  s.partial_measures.resize(static_cast<std::size_t>(p.threads));
  s.partial_impulses.resize(static_cast<std::size_t>(p.threads));
  s.measure = initial_measure(s.particles);
  return s;
}

}  // namespace compaction
