// Particle to grid transfer of the 3D column (APIC / MLS-MPM, Hu et al. 2018, Eq. 29), the
// 2D p2g.cpp's apic + mls path in three dimensions:
//   m_i += w m_p
//   (m v)_i += w (m_p v_p + Q_p d),  Q_p = -dt V0 D^-1 tau_p + m_p C_p,  d = x_i - x_p
// with D^-1 = 4 / dx^2 (kernel.hpp). Columns x and z wrap through grid.wrap (periodic).
#include <algorithm>

#include "kernel_3d.hpp"
#include "stages_3d.hpp"

namespace compaction {

void p2g_3d(State3D& s, double dt) {
  Grid3D& g = s.grid;
  const Particles3D& P = s.particles;
  const std::size_t layer = g.layer();
  std::fill(g.nodes.begin() + g.row_lo * layer, g.nodes.begin() + g.row_hi * layer,
            Node3D{0, 0, 0, 0});
  const double m = P.mass, dx = g.dx, inv_dx = g.inv_dx, gy = g.gy;
  const double stress = -dt * s.setup.scale;
  const int* wrap = g.wrap.data();
  Node3D* nodes = g.nodes.data();
  for (std::size_t p = 0; p < P.n; ++p) {
    const auto st = kernel::quadratic_3d(P.x[p] * inv_dx, P.y[p] * inv_dx + gy, P.z[p] * inv_dx);
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

}  // namespace compaction
