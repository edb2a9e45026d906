// The expected cost of a run before it runs: its particle-steps (particles x time steps to
// eps_end, both from the scene alone) times the time of one particle-step. The one home of the
// cost model: POST /api/v1/sweeps/estimate sums it over a sweep for the dashboard's form.
#pragma once

#include "compaction/params.hpp"

namespace compaction::server::cost {

// One particle-step on one core of the reference machine for the default transfer (APIC) and
// gradient (MLS), one velocity field, two runs sharing the two cores: 19.0 ns. Measured as the
// two-field runs of the six examples at the default preset, 33.4 ns per particle-step (median;
// 32.9-37.7), over kSplitFieldsFactor (bench/results/six_examples.md, 2026-12-05, engine 0.2.2,
// the AVX-512 copy of the particle loops; 18.5-20.1 ns alone on quiet cores,
// bench/results/cost_factors.md). A processor with AVX2 only takes about 1.25 times as long,
// one without AVX2 about 2.1.
inline constexpr double kNsPerParticleStep = 19.0;
// What the alternatives cost per particle-step, against the default, on one thread of a quiet
// machine: the median ratio of three runs of engine_bench's reference scene
// (bench/results/cost_factors.md, 2026-12-05, engine 0.2.2, the AVX-512 copy).
inline constexpr double kPicFlipFactor = 1.50;
inline constexpr double kBsplineFactor = 1.30;
// Two velocity fields across closing pores (pore_contact = split_fields), the same three runs:
// 1.68-1.83 times the default per particle-step (1.65 in four sessions of 2026-12-03, before
// G2P's node pairs made the one-field default faster; 2.03 before the two-field transfers
// were vectorised).
inline constexpr double kSplitFieldsFactor = 1.76;
// Full 2D: 49 ns against 29 per particle-step (wider rows, side walls; studies/savings/README.md).
inline constexpr double kFull2dFactor = 49.0 / 29.0;
// The 3D column (pseudo1d_3d, one thread) against the reference scene (one field), per
// particle-step in the same run of engine_bench: the median of three runs, 8.25
// (bench/results/return_map_3d_series.md, 2026-12-07, the return mapping by power series and the
// AVX-512 copy of the 3D loops; 11.76 before them).
inline constexpr double k3dFactor = 8.25;

// Particles: a regular structure's lattice less its holes, as the scene builders place them
// (21 726 for the pseudo-1D column at 20 cells per unit cell and phi = 0.4; 64 566 for the 3D
// column at 8 cells per unit cell and 2 x 2 x 2 particles per cell, where the hole of 13 of 16
// particles leaves a solid share of 0.46), phi times the lattice for a random one.
double particles(const SceneParams& p);
// Time steps to eps_final at the CFL step dt = cfl dx / (c_P + V), the plate speed standing
// for the fastest particle: eps h0 (c_P + V) / (V cfl dx) (237 946 for example (a) at 20 cells
// per unit cell to eps = 0.6; 237 626 measured).
double steps(const SceneParams& p);
// CPU seconds of the run on one core.
double cpu_seconds(const SceneParams& p);

}  // namespace compaction::server::cost
