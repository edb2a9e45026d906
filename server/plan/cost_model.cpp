#include "plan/cost_model.hpp"

#include <cmath>

namespace compaction::server::cost {

double particles(const SceneParams& p) {
  const int per_unit = p.grid_cells_per_unit() * p.particles_per_cell;
  const int dims = p.geometry == Geometry::pseudo1d_3d ? 3 : 2;
  const double lattice = std::pow(static_cast<double>(per_unit), dims);
  const double unit_cells = static_cast<double>(p.n_rows) * p.cols();
  if (p.structure == Structure::random) return p.phi * unit_cells * lattice;
  // A regular structure: the lattice less its hole, as the scene builders place them (none in
  // the solid column, phi = 1).
  return unit_cells * (lattice - std::pow(static_cast<double>(regular_void_side(p, per_unit)), dims));
}

double steps(const SceneParams& p) {
  // The engine's time step with the plate as the fastest particle, over the run's time.
  const double V = p.plate_speed();
  return p.eps_final() * p.h0 / V / cfl_time_step(p.cfl, p.grid_spacing(), p.p_wave_speed(), V);
}

double cpu_seconds(const SceneParams& p) {
  double ns = kNsPerParticleStep;
  if (p.transfer == Transfer::pic_flip) ns *= kPicFlipFactor;
  if (p.gradient == Gradient::bspline) ns *= kBsplineFactor;
  if (resolved_pore_contact(p) == PoreContact::split_fields) ns *= kSplitFieldsFactor;
  if (p.geometry == Geometry::full2d) ns *= kFull2dFactor;
  if (p.geometry == Geometry::pseudo1d_3d) ns *= k3dFactor;
  return particles(p) * steps(p) * ns * 1e-9;
}

}  // namespace compaction::server::cost
