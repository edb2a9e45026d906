// A solid column (phi = 1) hit by the top plate: a uniaxial-strain wave runs down at the
// P-wave speed c = sqrt((lambda + 2 mu) / rho), with stress rho c V behind it, and doubles on
// reflection at the fixed bottom plate (1D elastic wave theory).
#include <gtest/gtest.h>

#include <cmath>

#include "compaction/simulation.hpp"
#include "elastic_column_checks.hpp"

namespace compaction {
namespace {

struct Variant {
  Geometry geometry;
  Transfer transfer;
  PlateContact contact;
  Gradient gradient = Gradient::mls;
  PoreContact pore_contact = PoreContact::single_field;
};

SceneParams column(const Variant& v) {
  SceneParams p;
  p.geometry = v.geometry;
  p.transfer = v.transfer;
  p.contact = v.contact;
  p.gradient = v.gradient;
  p.pore_contact = v.pore_contact;
  p.phi = 1.0;
  p.S = 1e-3;
  p.R = 0.05;  // yield strain ~0.1 >> wave strain V / c ~ 1e-3: purely elastic
  p.n_cols = 3;
  p.cells_per_unit = 6;  // 204 cells along the column
  p.eps_end = 1.3e-3;    // the wave arrives at eps = V / c = S / 1.16 = 8.6e-4
  p.d_eps = 2e-6;        // frames fine enough to time the arrival to 0.3 %
  p.snapshot_eps = {};
  return p;
}

class ElasticColumnGtest : public ::testing::TestWithParam<Variant> {};

// The checks and their tolerances: elastic_column_checks.hpp.
TEST_P(ElasticColumnGtest, WaveSpeedAndStressBehindFrontMatchElasticTheory) {
  const SceneParams p = column(GetParam());
  const RunResult r = run_scene(p);
  ASSERT_EQ(r.status, RunStatus::ok) << r.reason;
  expect_elastic_column(p, r);
}

// Every transfer scheme and contact model: a compressive wave never pulls on a plate, so
// bonded and unilateral plates must agree. split_fields runs its own transfer loops (a column
// without pores keeps one field in them).
INSTANTIATE_TEST_SUITE_P(
    Variants, ElasticColumnGtest,
    ::testing::Values(Variant{Geometry::pseudo1d, Transfer::apic, PlateContact::bonded},
                      Variant{Geometry::full2d, Transfer::apic, PlateContact::bonded},
                      Variant{Geometry::pseudo1d, Transfer::pic_flip, PlateContact::bonded},
                      Variant{Geometry::pseudo1d, Transfer::apic, PlateContact::unilateral},
                      Variant{Geometry::pseudo1d, Transfer::apic, PlateContact::bonded,
                              Gradient::bspline},
                      Variant{Geometry::full2d, Transfer::apic, PlateContact::bonded,
                              Gradient::bspline},
                      Variant{Geometry::pseudo1d, Transfer::apic, PlateContact::bonded,
                              Gradient::mls, PoreContact::split_fields}),
    [](const auto& info) {
      return std::string(to_string(info.param.geometry)) + "_" +
             to_string(info.param.transfer) + "_" + to_string(info.param.contact) + "_" +
             to_string(info.param.gradient) + "_" + to_string(info.param.pore_contact);
    });

}  // namespace
}  // namespace compaction
