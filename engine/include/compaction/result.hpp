// The result of one compaction run: status, counts and timings, and the observables of the
// paper (space-time map of the plastic strain rate, plate stresses, particle snapshots) plus the
// per-frame diagnostics a classifier needs. This is the engine's public output type.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "compaction/params.hpp"

namespace compaction {

enum class RunStatus {
  ok,         // reached eps_end
  unstable,   // stopped by a stability check; reason and step say which and when
  cancelled,  // stopped on request (e.g. the worker was told to stop)
};

const char* to_string(RunStatus s);
bool parse(const std::string& s, RunStatus& out);

// Observables recorded once per frame (every d_eps of imposed strain).
struct Frame {
  double eps = 0.0;             // imposed strain V t / h0 at the end of the frame     [-]
  double sigma_top = 0.0;       // compressive stress of the top plate, frame average  [N/m]
  double sigma_bottom = 0.0;    // compressive stress of the bottom plate              [N/m]
  double kinetic_energy = 0.0;  // of all particles, per unit depth                    [J/m]
  double plate_work = 0.0;      // work done by both plates since t = 0                [J/m]
  double plastic_fraction = 0.0;   // share of particles that yielded in the frame     [-]
  double max_deflection = 0.0;  // largest lateral deflection of a vertical strut,
                                // midspan relative to its ends, / strut thickness    [-]
  double rms_deflection = 0.0;  // root mean square of the same over all struts       [-]
  double max_speed = 0.0;       // largest particle speed / V                          [-]
};

// Row-averaged plastic Hencky strain-rate magnitude |d eps_P / dt| / (V / h0).
// values[f * n_rows + r]: frame f, grid row r (height (r + 0.5) * row_height).
struct SpaceTimeMap {
  int n_rows = 0;
  int n_frames = 0;
  double row_height = 0.0;      // [m]
  std::vector<float> values;
  float at(int frame, int row) const { return values[static_cast<std::size_t>(frame) * n_rows + row]; }
};

// Particle state at one imposed strain.
struct Snapshot {
  double eps = 0.0;                  // imposed strain at which it was taken           [-]
  std::vector<float> x, y;           // current positions                             [m]
  std::vector<float> strain_rate;    // plastic strain rate over the last frame / (V/h0) [-]
  std::vector<float> plastic_strain; // accumulated plastic Hencky strain magnitude    [-]
  std::vector<float> jacobian;       // J = det F (particle area / initial area)       [-]
};

// Wall time of each stage of the time step, summed over the run.
struct StageTimes {
  double p2g = 0, grid_update = 0, g2p = 0, diagnostics = 0;  // [s]
};

struct RunResult {
  RunStatus status = RunStatus::ok;
  std::string reason;            // why the run is not ok (empty when ok)
  std::int64_t failed_step = -1; // step at which the instability was detected

  // Sizes and cost.
  std::int64_t n_particles = 0;
  int grid_nx = 0, grid_ny = 0;  // grid nodes
  double dx = 0.0;               // grid spacing                                   [m]
  double phi_discrete = 0.0;     // solid fraction the particles actually represent [-]
  std::int64_t steps = 0;
  double dt_mean = 0.0;          // [s]
  double eps_reached = 0.0;      // [-]
  double wall_seconds = 0.0;
  double ns_per_particle_step = 0.0;
  StageTimes stage_seconds;

  std::vector<Frame> frames;
  SpaceTimeMap spacetime;
  // Row-averaged vertical particle velocity / V at the end of each frame (same rows and
  // frames as spacetime; -1: moving with the top plate, 0: at rest). A compaction band is
  // where it jumps; the classifier follows reflected bands with it. Empty for bundles written
  // before it existed.
  SpaceTimeMap velocity;
  std::vector<Snapshot> snapshots;
};

// Version of the engine's numerics; part of the identity of a computed result.
const char* engine_version();
// Source revision (git commit, "-dirty" when built from a modified tree).
const char* source_revision();

}  // namespace compaction
