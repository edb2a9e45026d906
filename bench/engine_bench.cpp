// Engine speed on the reference scene: pseudo-1D, phi = 0.4, 20 cells per unit cell, 2 x 2
// particles per cell, S = 4e-3, R = 1e-5, ~3200 steps (eps 0 -> 0.008); on the large scene, the
// same column at 40 cells per unit cell (86 904 particles, the `reference` preset's grid at
// phi = 0.4), ~1600 steps (eps 0 -> 0.002); and on the 3D column at 8 cells per unit cell.
// One velocity field (pore_contact = single_field) unless the variant's name says SplitFields
// (two, the default preset's numerics on these scenes); one thread unless it says otherwise.
// Reports ns per particle-step (time-stepping loop only, scene building excluded) and its split
// by stage. Run it with bench/run_engine_bench.sh.
#include <benchmark/benchmark.h>

#include <string>

#include "compaction/simulation.hpp"

namespace {

compaction::SceneParams reference_scene() {
  compaction::SceneParams p;
  p.S = 4e-3, p.R = 1e-5, p.phi = 0.4;
  p.cells_per_unit = 20, p.particles_per_cell = 2;
  p.pore_contact = compaction::PoreContact::single_field;  // SceneParams' default is auto
  p.eps_end = 0.008;
  p.snapshot_eps = {};
  return p;
}

void report(benchmark::State& state, const compaction::RunResult& r) {
  state.SetLabel(std::string(compaction::simd_copy_name(compaction::simd_copy())) + " copy");
  const double per = 1e9 / (static_cast<double>(r.steps) * r.n_particles);
  state.counters["ns_per_particle_step"] = r.ns_per_particle_step;
  state.counters["p2g_ns"] = r.stage_seconds.p2g * per;
  state.counters["grid_ns"] = r.stage_seconds.grid_update * per;
  state.counters["g2p_ns"] = r.stage_seconds.g2p * per;
  state.counters["diag_ns"] = r.stage_seconds.diagnostics * per;
  state.counters["particles"] = static_cast<double>(r.n_particles);
  state.counters["steps"] = static_cast<double>(r.steps);
}

void run(benchmark::State& state, compaction::SceneParams p) {
  compaction::RunResult r;
  for (auto _ : state) {
    r = compaction::run_scene(p);
    benchmark::DoNotOptimize(r.frames.data());
  }
  if (r.status != compaction::RunStatus::ok) state.SkipWithError(r.reason.c_str());
  report(state, r);
}

void BM_ReferenceScene_Apic_1Thread(benchmark::State& state) { run(state, reference_scene()); }

void BM_ReferenceScene_PicFlip_1Thread(benchmark::State& state) {
  auto p = reference_scene();
  p.transfer = compaction::Transfer::pic_flip;
  run(state, p);
}

void BM_ReferenceScene_ApicBspline_1Thread(benchmark::State& state) {
  auto p = reference_scene();
  p.gradient = compaction::Gradient::bspline;
  run(state, p);
}

// Two velocity fields across closing pores (engine/src/pore_contact.hpp): P2G on one thread.
void BM_ReferenceScene_ApicSplitFields_1Thread(benchmark::State& state) {
  auto p = reference_scene();
  p.pore_contact = compaction::PoreContact::split_fields;
  run(state, p);
}

// The same scene on the narrower copies of the hot loops, as a processor without AVX-512 (the
// AVX2 copy) or without AVX2 (the baseline SSE2 copy) runs it; the other variants run the widest
// copy that the processor has (engine/src/simd_dispatch.hpp).
void run_on_copy(benchmark::State& state, compaction::SimdCopy copy) {
  compaction::use_simd_copy(copy);
  run(state, reference_scene());
  compaction::use_simd_copy(compaction::SimdCopy::avx512);
}

void BM_ReferenceScene_Apic_1Thread_Avx2Copy(benchmark::State& state) {
  run_on_copy(state, compaction::SimdCopy::avx2);
}

void BM_ReferenceScene_Apic_1Thread_BaselineCopy(benchmark::State& state) {
  run_on_copy(state, compaction::SimdCopy::baseline);
}

void BM_ReferenceScene_Apic_2Threads(benchmark::State& state) {
  auto p = reference_scene();
  p.threads = 2;
  run(state, p);
}

// The large scene, with one velocity field or with two across closing pores (what the
// presets' pore_contact = auto runs there), on one and on two threads.
compaction::SceneParams large_scene(compaction::PoreContact contact, int threads) {
  auto p = reference_scene();
  p.cells_per_unit = 40;
  p.eps_end = 0.002;
  p.pore_contact = contact;
  p.threads = threads;
  return p;
}

void BM_LargeScene_Apic_1Thread(benchmark::State& state) {
  run(state, large_scene(compaction::PoreContact::single_field, 1));
}
void BM_LargeScene_Apic_2Threads(benchmark::State& state) {
  run(state, large_scene(compaction::PoreContact::single_field, 2));
}
void BM_LargeScene_ApicSplitFields_1Thread(benchmark::State& state) {
  run(state, large_scene(compaction::PoreContact::split_fields, 1));
}
void BM_LargeScene_ApicSplitFields_2Threads(benchmark::State& state) {
  run(state, large_scene(compaction::PoreContact::split_fields, 2));
}

// The 3D column (geometry = pseudo1d_3d: one unit cell across in x and z) at 8 cells per unit
// cell, 2 x 2 x 2 particles per cell (64 566 particles), eps 0 -> 0.002 (317 steps), on one
// and on two threads.
compaction::SceneParams column_3d(int threads) {
  auto p = reference_scene();
  p.geometry = compaction::Geometry::pseudo1d_3d;
  p.cells_per_unit = 8;
  p.eps_end = 0.002;
  p.movie_d_eps = 0;
  p.threads = threads;
  return p;
}
void BM_Column3D_Apic_1Thread(benchmark::State& state) { run(state, column_3d(1)); }
void BM_Column3D_Apic_2Threads(benchmark::State& state) { run(state, column_3d(2)); }

}  // namespace

BENCHMARK(BM_ReferenceScene_Apic_1Thread)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_ReferenceScene_PicFlip_1Thread)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_ReferenceScene_ApicBspline_1Thread)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_ReferenceScene_ApicSplitFields_1Thread)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_ReferenceScene_Apic_1Thread_Avx2Copy)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_ReferenceScene_Apic_1Thread_BaselineCopy)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_ReferenceScene_Apic_2Threads)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_LargeScene_Apic_1Thread)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_LargeScene_Apic_2Threads)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_LargeScene_ApicSplitFields_1Thread)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_LargeScene_ApicSplitFields_2Threads)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Column3D_Apic_1Thread)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Column3D_Apic_2Threads)->Unit(benchmark::kMillisecond)->Iterations(1);

BENCHMARK_MAIN();
