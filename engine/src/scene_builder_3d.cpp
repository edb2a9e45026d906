#include "scene_builder_3d.hpp"

#include <algorithm>
#include <cmath>

#include "kernel.hpp"

namespace compaction {

namespace {

void build_grid(const SceneParams& p, Grid3D& g) {
  const int cells = p.grid_cells_per_unit();
  g.dx = p.grid_spacing();
  g.inv_dx = 1.0 / g.dx;
  g.cells_across = cells;
  g.cells_y = p.n_rows * cells;
  // Ghost layers below and above, as in 2D: a particle reaches one node beyond an edge.
  g.gy = 2;
  g.ny = g.cells_y + g.gy + 4;
  g.nx = g.nz = cells;
  g.wrap.resize(static_cast<std::size_t>(g.nx) + 3);
  for (int k = 0; k < g.nx + 3; ++k) g.wrap[k] = ((k - 1) % g.nx + g.nx) % g.nx;
  g.nodes.assign(g.layer() * g.ny, Node3D{0, 0, 0, 0});
  g.row_lo = 0;
  g.row_hi = g.ny;
  g.scratch.assign(static_cast<std::size_t>(p.threads - 1), g.nodes);
  g.scatter_rows.resize(p.threads, g.ny);
}

Setup3D make_setup(const SceneParams& p, const Grid3D& g, double vol0) {
  Setup3D su;
  su.material.lambda = p.lame_lambda();
  su.material.mu = p.lame_mu();
  su.material.dev_yield = p.q_y / (std::sqrt(6.0) * su.material.mu);
  su.V = p.plate_speed();
  su.h0 = p.h0;
  su.width = p.unit_cell();
  su.c_p = p.p_wave_speed();
  su.scale = vol0 * kernel::kInverseInertia * g.inv_dx * g.inv_dx;
  su.contact = p.contact;
  return su;
}

Particles3D place_particles(const SceneParams& p, const Grid3D& g) {
  const int per_unit = g.cells_across * p.particles_per_cell;  // particles per unit cell side
  const double spacing = g.dx / p.particles_per_cell;
  const int side = regular_void_side(p, per_unit);
  const int first = (per_unit - side) / 2, last = first + side;  // hole: [first, last)
  auto in_hole = [&](int l) { return l >= first && l < last; };

  Particles3D P;
  P.vol0 = spacing * spacing * spacing;
  P.mass = p.rho * P.vol0;
  const int npy = p.n_rows * per_unit;
  for (int j = 0; j < npy; ++j) {
    const bool hole_layer = in_hole(j % per_unit);
    for (int k = 0; k < per_unit; ++k) {
      for (int i = 0; i < per_unit; ++i) {
        if (hole_layer && in_hole(k) && in_hole(i)) continue;
        P.x.push_back((i + 0.5) * spacing);
        P.y.push_back((j + 0.5) * spacing);
        P.z.push_back((k + 0.5) * spacing);
      }
    }
  }
  P.n = P.x.size();
  P.vx.assign(P.n, 0.0);
  P.vy.assign(P.n, 0.0);
  P.vz.assign(P.n, 0.0);
  P.C.assign(P.n, Mat3::Zero());
  P.Fe.assign(P.n, Mat3::Identity());
  P.tau.assign(P.n, Mat3::Zero());
  P.dep.assign(P.n, 0.0);
  return P;
}

}  // namespace

State3D build_scene_3d(const SceneParams& p) {
  State3D s;
  build_grid(p, s.grid);
  s.particles = place_particles(p, s.grid);
  s.setup = make_setup(p, s.grid, s.particles.vol0);
  // The particles' extent in y, as a step would have measured it (the first step's layers).
  const auto [lo, hi] = std::minmax_element(s.particles.y.begin(), s.particles.y.end());
  s.measure.y_min = *lo;
  s.measure.y_max = *hi;
  s.partial_impulses.resize(static_cast<std::size_t>(p.threads));
  s.partial_measures.resize(static_cast<std::size_t>(p.threads));
  return s;
}

}  // namespace compaction
