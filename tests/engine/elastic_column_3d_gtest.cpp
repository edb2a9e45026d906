// The 3D solid column (phi = 1) hit by the top plate, as elastic_column_gtest in 2D: a
// uniaxial-strain wave runs down at the P-wave speed c = sqrt((lambda + 2 mu) / rho), with
// stress rho c V behind it, and doubles on reflection at the fixed bottom plate (1D elastic
// wave theory). A column without holes is uniform across, so two cells across (periodic in x
// and z) stand for any width; 102 unit cells of 2 grid cells give the 204 cells along y of the
// 2D test.
#include <gtest/gtest.h>

#include <string>

#include "compaction/simulation.hpp"
#include "elastic_column_checks.hpp"

namespace compaction {
namespace {

SceneParams column(PlateContact contact) {
  SceneParams p;
  p.geometry = Geometry::pseudo1d_3d;
  p.phi = 1.0;
  p.S = 1e-3;
  p.R = 0.05;  // yield strain ~0.1 >> wave strain V / c ~ 1e-3: purely elastic
  p.n_rows = 102;
  p.cells_per_unit = 2;  // 204 cells along the column, 2 across
  p.contact = contact;
  p.eps_end = 1.3e-3;  // the wave arrives at eps = V / c = S / 1.16 = 8.6e-4
  p.d_eps = 2e-6;      // frames fine enough to time the arrival to 0.3 %
  p.snapshot_eps = {};
  p.movie_d_eps = 0.0;
  return p;
}

class ElasticColumn3dGtest : public ::testing::TestWithParam<PlateContact> {};

// The checks and their tolerances: elastic_column_checks.hpp.
TEST_P(ElasticColumn3dGtest, WaveSpeedAndStressBehindFrontMatchElasticTheory) {
  const SceneParams p = column(GetParam());
  const RunResult r = run_scene(p);  // validated, then simulation_3d.cpp's loop
  ASSERT_EQ(r.status, RunStatus::ok) << r.reason;
  expect_elastic_column(p, r);
}

INSTANTIATE_TEST_SUITE_P(Contacts, ElasticColumn3dGtest,
                         ::testing::Values(PlateContact::bonded, PlateContact::unilateral),
                         [](const auto& info) { return std::string(to_string(info.param)); });

}  // namespace
}  // namespace compaction
