// The constitutive update alone, per call: the 2D closed form (plasticity.hpp) against the 3D
// return mapping (plasticity_3d.hpp) by its power series and in principal space, and the
// eigen-decomposition of b the principal update needs three ways: the Jacobi rotations it uses
// (sym_eigen_3d.hpp), Eigen's iterative solver
// (SelfAdjointEigenSolver::compute) and Eigen's closed form (computeDirect, not accurate enough
// for the column's equal eigenvalues). This is what bounds the 3D engine's G2P
// (docs/engine.md, "The 3D column").
//
// States: 4 096 deformation gradients of a column compressed along y, as the engine meets them:
// F = R (diag(1, 1 - e, 1) + G) with e uniform in [0, 0.02], G a shear of up to 1e-3 and R a
// rotation of up to 0.1 rad; the yield strain is set so that about half of them yield. Each call
// starts from the same trial state (the update writes Fe in place; the copy is part of the loop
// in every variant). Run it with bench/run_return_map_bench.sh.
#include <benchmark/benchmark.h>

#include <Eigen/Dense>
#include <random>
#include <vector>

#include "plasticity.hpp"
#include "plasticity_3d.hpp"
#include "sym_eigen_3d.hpp"

namespace {

using compaction::Mat3;

constexpr std::size_t kStates = 4096;

std::vector<Mat3> states_3d() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> strain(0.0, 0.02), shear(-1e-3, 1e-3), angle(-0.1, 0.1);
  std::vector<Mat3> out(kStates);
  for (auto& f : out) {
    Mat3 g = Mat3::Identity();
    g(1, 1) -= strain(rng);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i != j) g(i, j) += shear(rng);
    const Eigen::Vector3d axis = Eigen::Vector3d(shear(rng), shear(rng), shear(rng)).normalized();
    f = Eigen::AngleAxisd(angle(rng), axis).toRotationMatrix() * g;
  }
  return out;
}

constexpr double kE = 1e6, kNu = 0.3;
constexpr double kLambda = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), kMu = kE / (2 * (1 + kNu));

// About half the states yield: uniaxial strain e has |dev(e)| = sqrt(2/3) e in 3D and a
// principal difference d_e = e in 2D, so the yield strains below put the median e = 0.01 at
// yield.
compaction::Material3D material_3d() { return {kLambda, kMu, std::sqrt(2.0 / 3.0) * 0.01}; }
compaction::Material material_2d() { return {kLambda, kMu, 0.01}; }

// Seconds per call (Google Benchmark prints it with a prefix, "230n"; the JSON holds seconds).
void per_call(benchmark::State& state, std::size_t yielded) {
  state.counters["s_per_call"] = benchmark::Counter(
      static_cast<double>(kStates),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  if (yielded > 0) state.counters["yielded_fraction"] = static_cast<double>(yielded) / kStates;
}

void BM_ReturnMap2D(benchmark::State& state) {
  std::vector<compaction::Mat2> in(kStates);
  const auto s3 = states_3d();
  for (std::size_t i = 0; i < kStates; ++i)
    in[i] = {s3[i](0, 0), s3[i](0, 1), s3[i](1, 0), s3[i](1, 1)};
  const auto m = material_2d();
  compaction::Sym2 tau{};
  std::size_t yielded = 0;
  for (auto _ : state) {
    yielded = 0;
    for (const auto& f0 : in) {
      compaction::Mat2 f = f0;
      yielded += compaction::return_map(f, m, tau) > 0.0;
      benchmark::DoNotOptimize(tau);
    }
  }
  per_call(state, yielded);
}

template <double (*kReturnMap)(Mat3&, const compaction::Material3D&, Mat3&)>
void return_map_3d_calls(benchmark::State& state) {
  const auto in = states_3d();
  const auto m = material_3d();
  Mat3 tau;
  std::size_t yielded = 0;
  for (auto _ : state) {
    yielded = 0;
    for (const auto& f0 : in) {
      Mat3 f = f0;
      yielded += kReturnMap(f, m, tau) > 0.0;
      benchmark::DoNotOptimize(tau);
    }
  }
  per_call(state, yielded);
}

// What the engine runs: the power series, the principal update where they do not hold (none of
// these states).
void BM_ReturnMap3D(benchmark::State& state) {
  return_map_3d_calls<compaction::return_map_3d>(state);
}

// The update in principal space (Jacobi rotations) for every state.
void BM_ReturnMap3D_Principal(benchmark::State& state) {
  return_map_3d_calls<compaction::return_map_3d_principal>(state);
}

void BM_EigenSolver3D_Compute(benchmark::State& state) {
  const auto in = states_3d();
  for (auto _ : state) {
    for (const auto& f : in) {
      const Eigen::SelfAdjointEigenSolver<Mat3> eig(f * f.transpose());
      benchmark::DoNotOptimize(eig.eigenvalues().data());
      benchmark::DoNotOptimize(eig.eigenvectors().data());
    }
  }
  per_call(state, 0);
}

void BM_EigenSolver3D_Jacobi(benchmark::State& state) {
  const auto in = states_3d();
  for (auto _ : state) {
    for (const auto& f : in) {
      const compaction::SymEigen3 eig = compaction::sym_eigen_3d(f * f.transpose());
      benchmark::DoNotOptimize(eig.l.data());
      benchmark::DoNotOptimize(eig.q.data());
    }
  }
  per_call(state, 0);
}

void BM_EigenSolver3D_ComputeDirect(benchmark::State& state) {
  const auto in = states_3d();
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  for (auto _ : state) {
    for (const auto& f : in) {
      eig.computeDirect(f * f.transpose());
      benchmark::DoNotOptimize(eig.eigenvalues().data());
      benchmark::DoNotOptimize(eig.eigenvectors().data());
    }
  }
  per_call(state, 0);
}

}  // namespace

BENCHMARK(BM_ReturnMap2D);
BENCHMARK(BM_ReturnMap3D);
BENCHMARK(BM_ReturnMap3D_Principal);
BENCHMARK(BM_EigenSolver3D_Compute);
BENCHMARK(BM_EigenSolver3D_Jacobi);
BENCHMARK(BM_EigenSolver3D_ComputeDirect);

BENCHMARK_MAIN();
