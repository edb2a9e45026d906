// Grid to particle transfer of the 3D column, then each particle's own update (Hu et al. 2018,
// Eqs. 17-19, 30), the 2D g2p.cpp's apic + mls path in three dimensions:
//   v_p = sum w v_i,  C_p = D^-1 sum w v_i (x_i - x_p)^T  (= the velocity gradient)
//   x_p += dt v_p (x and z wrapped into [0, width)),  Fe <- (I + dt C_p) Fe,
// then the return mapping (plasticity_3d.hpp) gives Fe and the Kirchhoff stress.
#include <algorithm>
#include <cmath>

#include "kernel_3d.hpp"
#include "simd_dispatch.hpp"
#include "stages_3d.hpp"

namespace compaction {

namespace {

// Particles [begin, end); returns what they measure. Compiled once for each copy of the loops
// (run_variant, simd_dispatch.hpp), as p2g_3d.cpp's Scatter3D and for the same reason.
struct UpdateParticles3D {
  template <bool kAvx2>
  [[gnu::always_inline]] static StepMeasure run(State3D& s, double dt, std::size_t begin,
                                                std::size_t end) {
    const Grid3D& g = s.grid;
    Particles3D& P = s.particles;
    const std::size_t layer = g.layer();
    const double dx = g.dx, inv_dx = g.inv_dx, gy = g.gy, width = s.setup.width;
    const double c_scale = kernel::kInverseInertia * inv_dx * inv_dx;
    const int* wrap = g.wrap.data();
    const Node3D* nodes = g.nodes.data();
    StepMeasure m;
    m.y_min = 1e300;
    m.y_max = -1e300;
    for (std::size_t p = begin; p < end; ++p) {
      const auto st = kernel::quadratic_3d(P.x[p] * inv_dx, P.y[p] * inv_dx + gy, P.z[p] * inv_dx);
      int col[3], dep[3];
      for (int a = 0; a < 3; ++a) {
        col[a] = wrap[st.x.base + 1 + a];
        dep[a] = wrap[st.z.base + 1 + a];
      }
      // v = sum w v_i and B = sum w v_i d^T in scalars (B[r][c] += w v_r d_c): Eigen's outer
      // product here cost g2p five times p2g's transfer (perf, 7280 particles).
      double v[3] = {0, 0, 0}, B[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
      for (int b = 0; b < 3; ++b) {
        const std::size_t row = static_cast<std::size_t>(st.y.base + b) * layer;
        const double dy = (b - st.y.fx) * dx;
        for (int c = 0; c < 3; ++c) {
          const double dz = (c - st.z.fx) * dx;
          const Node3D* line = nodes + row + static_cast<std::size_t>(dep[c]) * g.nx;
          for (int a = 0; a < 3; ++a) {
            const double w = st.w[(b * 3 + c) * 3 + a];
            const Node3D& n = line[col[a]];
            const double wv[3] = {w * n.vx, w * n.vy, w * n.vz};
            const double d[3] = {(a - st.x.fx) * dx, dy, dz};
            for (int r = 0; r < 3; ++r) {
              v[r] += wv[r];
              for (int k = 0; k < 3; ++k) B[r][k] += wv[r] * d[k];
            }
          }
        }
      }
      Mat3 b_sum;
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) b_sum(r, k) = B[r][k];
      const Mat3 C = c_scale * b_sum;
      P.vx[p] = v[0], P.vy[p] = v[1], P.vz[p] = v[2];
      P.C[p] = C;
      double x = P.x[p] + dt * v[0], z = P.z[p] + dt * v[2];
      x = x >= width ? x - width : (x < 0.0 ? x + width : x);
      z = z >= width ? z - width : (z < 0.0 ? z + width : z);
      P.x[p] = x, P.z[p] = z;
      P.y[p] += dt * v[1];
      P.Fe[p] = ((Mat3::Identity() + dt * C) * P.Fe[p]).eval();
      const double plastic = return_map_3d(P.Fe[p], s.setup.material, P.tau[p]);
      if (std::isnan(plastic)) {
        m.bad_jacobian = true;
      } else {
        P.dep[p] += plastic;
      }
      const double v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
      m.max_v2 = std::isnan(v2) || std::isnan(m.max_v2) ? std::nan("") : std::max(m.max_v2, v2);
      m.y_min = std::min(m.y_min, P.y[p]);
      m.y_max = std::max(m.y_max, P.y[p]);
    }
    return m;
  }
};

}  // namespace

// With threads, each updates a share of the particles (each writes only its own); their
// measures are combined (state.hpp's combine).
void g2p_3d(State3D& s, double dt, ThreadPool& pool) {
  const std::size_t n = s.particles.n;
  pool.run([&](int t) {
    s.partial_measures[t] = run_variant<UpdateParticles3D>(s, dt, pool.begin(n, t), pool.end(n, t));
  });
  StepMeasure m = s.partial_measures[0];
  for (int t = 1; t < pool.size(); ++t) m = combine(m, s.partial_measures[t]);
  s.measure = m;
}

}  // namespace compaction
