// The solid column's elastic checks, the same for the 2D and the 3D engine
// (elastic_column_gtest, elastic_column_3d_gtest): a plate moving at V into a column of
// phi = 1 sends a front at c_P with stress rho c_P V behind it, doubled where it reflects at the
// bottom plate. Tolerances: 2 % on the speed (the front is smeared over a few cells by the
// B-spline transfers, and the plate acts on nodes within one cell of its position: 1/204 of the
// height), 3 % on the stresses (averages over the plateaus; Kirchhoff and Cauchy stress differ
// by J - 1 ~ 1e-3).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "compaction/simulation.hpp"

namespace compaction {

// Wave speed from the first frame in which the bottom plate carries half the reflected
// stress (2 rho c V): time of flight over the height h0.
inline double measured_wave_speed(const SceneParams& p, const RunResult& r) {
  const double rho_c_v = p.rho * p.p_wave_speed() * p.plate_speed();
  for (std::size_t f = 1; f < r.frames.size(); ++f) {
    if (r.frames[f].sigma_bottom >= rho_c_v) {
      // Linear interpolation between the frames around the crossing.
      const Frame &a = r.frames[f - 1], &b = r.frames[f];
      const double eps = a.eps + (rho_c_v - a.sigma_bottom) / (b.sigma_bottom - a.sigma_bottom) *
                                     (b.eps - a.eps);
      return p.h0 / (eps * p.h0 / p.plate_speed());
    }
  }
  return 0.0;
}

// The wave speed, the stress behind the front at the top plate and the reflected stress at
// the bottom plate of a solid column's run, each recorded as a test property.
inline void expect_elastic_column(const SceneParams& p, const RunResult& r) {
  const double c = p.p_wave_speed();
  const double speed_ratio = measured_wave_speed(p, r) / c;
  ::testing::Test::RecordProperty("wave_speed_ratio", std::to_string(speed_ratio));
  EXPECT_NEAR(speed_ratio, 1.0, 0.02);

  const double rho_c_v = p.rho * c * p.plate_speed();
  const double arrival = p.plate_speed() / c;  // eps at which the front reaches the bottom
  double sum = 0.0;
  int n = 0;
  for (const Frame& f : r.frames) {
    if (f.eps > 0.2 * arrival && f.eps < 0.9 * arrival) sum += f.sigma_top, ++n;
  }
  ASSERT_GT(n, 10);
  ::testing::Test::RecordProperty("stress_ratio", std::to_string(sum / n / rho_c_v));
  EXPECT_NEAR(sum / n / rho_c_v, 1.0, 0.03);
  // After the reflection the bottom plate carries twice the incident stress.
  double bottom = 0.0;
  int m = 0;
  for (const Frame& f : r.frames) {
    if (f.eps > 1.15 * arrival && f.eps < 1.45 * arrival) bottom += f.sigma_bottom, ++m;
  }
  ASSERT_GT(m, 10);
  ::testing::Test::RecordProperty("reflected_stress_ratio",
                                  std::to_string(bottom / m / (2 * rho_c_v)));
  EXPECT_NEAR(bottom / m / (2 * rho_c_v), 1.0, 0.03);
}

}  // namespace compaction
