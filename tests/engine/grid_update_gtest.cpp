// Grid update: on two or three threads it gives one thread's node velocities and plate
// impulses bit for bit (each plate lies in one thread's rows, and a node's update is its own),
// with one and two velocity fields, with PIC/FLIP's momenta and with side walls.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "scene_builder.hpp"
#include "stages.hpp"
#include "threaded_grid.hpp"

namespace compaction {
namespace {

struct Case {
  Geometry geometry;
  PoreContact contact;
  Transfer transfer;
};

// A short column after one P2G, its particles moving down at half the plate speed with a little
// sideways motion, so that both plates (and in full 2D the walls) act on it.
State column(const Case& c) {
  SceneParams p;
  p.S = 0.004, p.R = 1e-4, p.phi = 0.4, p.eps_end = 0.01;
  p.cells_per_unit = 14;  // 3.2 cells across a strut: split_fields' minimum is 3
  p.n_rows = 6, p.n_cols = 2;
  p.geometry = c.geometry, p.pore_contact = c.contact, p.transfer = c.transfer;
  State s = build_scene(p);
  Particles& P = s.particles;
  for (std::size_t k = 0; k < P.n; ++k) {
    P.vy[k] = -0.5 * s.setup.V;
    P.vx[k] = 0.1 * s.setup.V * std::sin(0.37 * static_cast<double>(k));
  }
  s.grid.row_lo = 0, s.grid.row_hi = s.grid.ny;
  ThreadPool one(1);
  p2g(s, 1e-7, one);
  return s;
}

TEST(GridUpdateGtest, ThreadsGiveOneThreadsBits) {
  const Case cases[] = {
      {Geometry::pseudo1d, PoreContact::single_field, Transfer::apic},
      {Geometry::pseudo1d, PoreContact::split_fields, Transfer::apic},
      {Geometry::pseudo1d, PoreContact::single_field, Transfer::pic_flip},
      {Geometry::full2d, PoreContact::split_fields, Transfer::apic},
  };
  for (const Case& c : cases) {
    State a = column(c);
    ThreadPool one(1);
    grid_update(a, one);
    ASSERT_TRUE(a.setup.split_fields == (c.contact == PoreContact::split_fields));
    EXPECT_LT(a.clock.top_impulse, 0.0);     // the top plate holds the material back
    EXPECT_GT(a.clock.bottom_impulse, 0.0);  // the bottom plate stops it
    for (int threads : {2, 3}) {
      State b = column(c);
      size_for_threads(b, threads);
      ThreadPool pool(threads);
      grid_update(b, pool);
      const auto& x = a.grid.arrays;
      const auto& y = b.grid.arrays;
      ASSERT_EQ(x.nodes.size(), y.nodes.size());
      EXPECT_EQ(std::memcmp(x.nodes.data(), y.nodes.data(), x.nodes.size() * sizeof(Node)), 0)
          << threads << " threads";
      EXPECT_EQ(x.mx, y.mx);
      EXPECT_EQ(x.my, y.my);
      EXPECT_EQ(a.clock.top_impulse, b.clock.top_impulse) << threads << " threads";
      EXPECT_EQ(a.clock.bottom_impulse, b.clock.bottom_impulse) << threads << " threads";
      EXPECT_EQ(a.clock.plate_work, b.clock.plate_work) << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace compaction
