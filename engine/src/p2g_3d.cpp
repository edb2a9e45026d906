// Particle to grid transfer of the 3D column (APIC / MLS-MPM, Hu et al. 2018, Eq. 29), the
// 2D p2g.cpp's apic + mls path in three dimensions:
//   m_i += w m_p
//   (m v)_i += w (m_p v_p + Q_p d),  Q_p = -dt V0 D^-1 tau_p + m_p C_p,  d = x_i - x_p
// with D^-1 = 4 / dx^2 (kernel.hpp). Columns x and z wrap through grid.wrap (periodic).
// With threads, as in 2D (scatter_rows.hpp, a row being a y-layer): each thread scatters a share
// of the particles, into the grid where its layers are its own, else into its scratch grid,
// summed into the grid afterwards in thread order. One thread adds every particle to the grid in
// order, so its result has the bits of the loop without threads.
#include <algorithm>

#include "kernel_3d.hpp"
#include "simd_dispatch.hpp"
#include "stages_3d.hpp"

namespace compaction {

namespace {

// Particles [begin, end) into `own` (null: all into the grid), or into the grid where their
// three layers are `alone` to this thread. run_variant (simd_dispatch.hpp) compiles it once for
// each copy of the loops: the wide copies are encoded in VEX, so they do not wait on the upper
// halves of vector registers that the 2D copies or the C library left set, as legacy SSE code
// does (a 3D run after a 2D one in the same process took 2.6 times as long in SSE).
struct Scatter3D {
  template <bool kAvx2>
  [[gnu::always_inline]] static void run(const State3D& s, double dt, std::size_t begin,
                                         std::size_t end, Node3D* grid, Node3D* own,
                                         const std::uint8_t* alone) {
    const Grid3D& g = s.grid;
    const Particles3D& P = s.particles;
    const std::size_t layer = g.layer();
    const double m = P.mass, dx = g.dx, inv_dx = g.inv_dx, gy = g.gy;
    const double stress = -dt * s.setup.scale;
    const int* wrap = g.wrap.data();
    for (std::size_t p = begin; p < end; ++p) {
      const auto st = kernel::quadratic_3d(P.x[p] * inv_dx, P.y[p] * inv_dx + gy, P.z[p] * inv_dx);
      Node3D* nodes = own != nullptr && !alone[st.y.base] ? own : grid;
      const Mat3 q = stress * P.tau[p] + m * P.C[p];
      const double mvx = m * P.vx[p], mvy = m * P.vy[p], mvz = m * P.vz[p];
      int col[3], dep[3];
      for (int a = 0; a < 3; ++a) {
        col[a] = wrap[st.x.base + 1 + a];
        dep[a] = wrap[st.z.base + 1 + a];
      }
      for (int b = 0; b < 3; ++b) {
        const std::size_t row = static_cast<std::size_t>(st.y.base + b) * layer;
        const double dy = (b - st.y.fx) * dx;
        for (int c = 0; c < 3; ++c) {
          const double dz = (c - st.z.fx) * dx;
          Node3D* line = nodes + row + static_cast<std::size_t>(dep[c]) * g.nx;
          for (int a = 0; a < 3; ++a) {
            const double w = st.w[(b * 3 + c) * 3 + a];
            const double ddx = (a - st.x.fx) * dx;
            Node3D& n = line[col[a]];
            n.m += w * m;
            n.vx += w * (mvx + q(0, 0) * ddx + q(0, 1) * dy + q(0, 2) * dz);
            n.vy += w * (mvy + q(1, 0) * ddx + q(1, 1) * dy + q(1, 2) * dz);
            n.vz += w * (mvz + q(2, 0) * ddx + q(2, 1) * dy + q(2, 2) * dz);
          }
        }
      }
    }
  }
};

}  // namespace

void p2g_3d(State3D& s, double dt, ThreadPool& pool) {
  Grid3D& g = s.grid;
  const std::size_t layer = g.layer(), n = s.particles.n;
  const std::size_t lo = static_cast<std::size_t>(g.row_lo) * layer;
  const std::size_t count = static_cast<std::size_t>(g.row_hi - g.row_lo) * layer;
  const bool threads = pool.size() > 1;
  ScatterRows& rows = g.scatter_rows;
  const int row_count = g.row_hi - g.row_lo;
  // 1. The grid's layers zeroed, a share each; the layers each thread's particles reach.
  pool.run([&](int t) {
    std::fill(g.nodes.begin() + lo + pool.begin(count, t), g.nodes.begin() + lo + pool.end(count, t),
              Node3D{0, 0, 0, 0});
    if (threads) {
      stencil_rows(s.particles.y.data(), pool.begin(n, t), pool.end(n, t), g.inv_dx, g.gy, rows.lo[t],
                   rows.hi[t]);
    }
  });
  if (threads) rows.plan(g.row_lo, g.row_hi);
  // 2. Mass and momentum: thread 0 into the grid, the others into the grid or their scratch
  // (zeroed first on the layers near a shared one, the only ones they write there).
  pool.run([&](int t) {
    if (t == 0) {
      run_variant<Scatter3D>(s, dt, pool.begin(n, t), pool.end(n, t), g.nodes.data(),
                             static_cast<Node3D*>(nullptr),
                             static_cast<const std::uint8_t*>(nullptr));
      return;
    }
    std::vector<Node3D>& own = g.scratch[static_cast<std::size_t>(t - 1)];
    for (int r = std::max(rows.lo[t], g.row_lo); r < std::min(rows.hi[t], g.row_hi); ++r) {
      if (rows.near[r]) std::fill_n(own.begin() + static_cast<std::size_t>(r) * layer, layer, Node3D{0, 0, 0, 0});
    }
    run_variant<Scatter3D>(s, dt, pool.begin(n, t), pool.end(n, t), g.nodes.data(), own.data(),
                           static_cast<const std::uint8_t*>(rows.alone.data()));
  });
  if (!threads) return;
  // 3. The scratch summed into the grid on the layers near a shared one, thread 1 first: the
  // result does not depend on timing.
  pool.run([&](int t) {
    const int r0 = g.row_lo + static_cast<int>(pool.begin(static_cast<std::size_t>(row_count), t));
    const int r1 = g.row_lo + static_cast<int>(pool.end(static_cast<std::size_t>(row_count), t));
    for (int r = r0; r < r1; ++r) {
      if (!rows.near[r]) continue;
      for (std::size_t u = 0; u < g.scratch.size(); ++u) {
        if (!rows.reaches(static_cast<int>(u) + 1, r)) continue;
        const Node3D* src = g.scratch[u].data() + static_cast<std::size_t>(r) * layer;
        Node3D* dst = g.nodes.data() + static_cast<std::size_t>(r) * layer;
        for (std::size_t k = 0; k < layer; ++k) {
          dst[k].m += src[k].m, dst[k].vx += src[k].vx, dst[k].vy += src[k].vy, dst[k].vz += src[k].vz;
        }
      }
    }
  });
}

}  // namespace compaction
