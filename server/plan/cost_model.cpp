#include "plan/cost_model.hpp"

namespace compaction::server::cost {

double particles(const SceneParams& p) {
  const double cells = static_cast<double>(p.grid_cells_per_unit());
  const double ppc = static_cast<double>(p.particles_per_cell);
  return p.phi * p.n_rows * p.cols() * cells * cells * ppc * ppc;
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
  return particles(p) * steps(p) * ns * 1e-9;
}

}  // namespace compaction::server::cost
