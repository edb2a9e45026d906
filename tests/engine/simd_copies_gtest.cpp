// The hot loops' AVX2 and AVX-512 copies give the same result bits as their baseline copy
// (engine/src/simd_dispatch.hpp), so that a result does not depend on the processor a worker
// runs on. A copy that this processor cannot run is skipped. Small scenes that reach every
// variant of both loops: APIC and PIC/FLIP, MLS and B-spline gradients, plastic particles and
// particles whose large elastic strains (R = 0.1) need the return mapping's long series,
// pseudo-1D and full 2D, one and two threads; and the 3D column (its scatter and its particle
// update with the series return mapping), yielding, on two threads.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "compaction/simulation.hpp"
#include "small_column_3d.hpp"

namespace compaction {
namespace {

SceneParams scene(double S, double R) {
  SceneParams p;
  p.S = S, p.R = R, p.phi = 0.4, p.cells_per_unit = 6, p.eps_end = 0.05;
  p.perturbation = 0.05, p.seed = 11, p.snapshot_eps = {0.04};
  return p;
}

template <class T>
bool same(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void expect_same_bits(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_TRUE(same(a.frames, b.frames)) << "frames differ";
  EXPECT_TRUE(same(a.spacetime.values, b.spacetime.values)) << "space-time map differs";
  EXPECT_TRUE(same(a.velocity.values, b.velocity.values)) << "velocity map differs";
  ASSERT_EQ(a.snapshots.size(), b.snapshots.size());
  for (std::size_t i = 0; i < a.snapshots.size(); ++i) {
    EXPECT_TRUE(same(a.snapshots[i].x, b.snapshots[i].x) && same(a.snapshots[i].y, b.snapshots[i].y))
        << "positions differ";
    EXPECT_TRUE(same(a.snapshots[i].jacobian, b.snapshots[i].jacobian)) << "J differs";
    EXPECT_TRUE(same(a.snapshots[i].plastic_strain, b.snapshots[i].plastic_strain))
        << "plastic strain differs";
  }
}

class SimdCopiesGtest : public testing::TestWithParam<std::string> {
 protected:
  void TearDown() override { use_simd_copy(SimdCopy::avx512); }
};

SceneParams case_params(const std::string& name) {
  SceneParams p = scene(0.05, 1e-3);
  if (name == "ApicMlsPlasticBand") return p;
  if (name == "LargeElasticStrainTakesTheLongSeries") return scene(0.05, 0.1);
  if (name == "PicFlipBspline") {
    p.transfer = Transfer::pic_flip, p.gradient = Gradient::bspline;
    return p;
  }
  if (name == "Full2dBsplineTwoThreads") {
    p = scene(0.05, 4e-4);
    p.geometry = Geometry::full2d, p.n_cols = 3, p.n_rows = 8;
    p.gradient = Gradient::bspline, p.threads = 2;
    return p;
  }
  if (name == "Column3dPlasticTwoThreads") {
    p = small_column_3d();
    p.threads = 2;
    return p;
  }
  p = scene(0.02, 4e-4);  // "ApicMlsTwoThreads"
  p.threads = 2;
  return p;
}

// The scene on the given wide copy and on the baseline copy, bit for bit.
void expect_baseline_bits(SimdCopy wide_copy, const std::string& scene) {
  use_simd_copy(wide_copy);
  if (simd_copy() != wide_copy) {
    GTEST_SKIP() << "no " << simd_copy_name(wide_copy) << " copy on this build or processor";
  }
  const SceneParams p = case_params(scene);
  const RunResult wide = run_scene(p);
  use_simd_copy(SimdCopy::baseline);
  ASSERT_EQ(simd_copy(), SimdCopy::baseline);
  const RunResult base = run_scene(p);
  ASSERT_EQ(wide.status, RunStatus::ok) << wide.reason;
  ASSERT_EQ(base.status, RunStatus::ok) << base.reason;
  expect_same_bits(wide, base);
}

TEST_P(SimdCopiesGtest, Avx2CopyGivesTheBaselineBits) {
  expect_baseline_bits(SimdCopy::avx2, GetParam());
}

TEST_P(SimdCopiesGtest, Avx512CopyGivesTheBaselineBits) {
  expect_baseline_bits(SimdCopy::avx512, GetParam());
}

INSTANTIATE_TEST_SUITE_P(Scenes, SimdCopiesGtest,
                         testing::Values("ApicMlsPlasticBand",
                                         "LargeElasticStrainTakesTheLongSeries",
                                         "PicFlipBspline", "Full2dBsplineTwoThreads",
                                         "ApicMlsTwoThreads", "Column3dPlasticTwoThreads"),
                         [](const testing::TestParamInfo<std::string>& i) { return i.param; });

}  // namespace
}  // namespace compaction
