// Grid to particle transfer, then the particle's own update (Hu et al. 2018, Eqs. 17-19, 30):
//   v_p = sum w v_i                     (apic; pic_flip blends in the FLIP increment)
//   C_p = D^-1 sum w v_i (x_i - x_p)^T  (= the velocity gradient for quadratic B-splines)
//   x_p += dt v_p,  Fe <- (I + dt C_p) Fe,  then the return mapping (plasticity.hpp), run on
//   blocks of kBlock particles at a time so that it vectorises across them.
// gradient = bspline updates Fe with the exact gradient sum v_i (x) grad w_ip instead of C_p.
#include <algorithm>
#include <cmath>
#include <limits>

#include "kernel.hpp"
#include "simd_clones.hpp"
#include "stages.hpp"

namespace compaction {

namespace {

template <bool kApic, bool kExact>
COMPACTION_SIMD_CLONES StepMeasure gather(Particles& P, const Setup& s, const Grid& g, std::size_t begin,
                   std::size_t end, double dt) {
  const double dx = g.dx, inv_dx = g.inv_dx;
  const double c_scale = kernel::kInverseInertia * inv_dx * inv_dx;
  const int nx = g.nx;
  const int* col = g.col.data();
  const Node* nodes = g.arrays.nodes.data();
  const double alpha = s.flip_ratio;
  const bool periodic = g.periodic_x;
  const double width = s.width;
  StepMeasure m;
  m.y_min = m.x_min = std::numeric_limits<double>::infinity();
  m.y_max = m.x_max = -std::numeric_limits<double>::infinity();
  ReturnMapBlock blk;  // the block's trial Fe in; Fe, tau and the plastic increment out
  for (std::size_t b0 = begin; b0 < end; b0 += kBlock) {
    const std::size_t nb = std::min(kBlock, end - b0);
    for (std::size_t i = 0; i < nb; ++i) {
      const std::size_t p = b0 + i;
      const auto kx = kernel::quadratic(P.x[p] * inv_dx + g.gx);
      const auto ky = kernel::quadratic(P.y[p] * inv_dx + g.gy);
      // B = sum_ab wx_a wy_b v_ab (dx_a, dy_b)^T, summed row by row with the x-weights
      // (and x-weighted offsets) applied first.
      const double wdx[3] = {kx.w[0] * (0 - kx.fx) * dx, kx.w[1] * (1 - kx.fx) * dx,
                             kx.w[2] * (2 - kx.fx) * dx};
      double vx = 0, vy = 0, bxx = 0, bxy = 0, byx = 0, byy = 0, ox = 0, oy = 0;
      double gxx = 0, gxy = 0, gyx = 0, gyy = 0;  // exact velocity gradient (times dx)
      for (int b = 0; b < 3; ++b) {
        const double wy = ky.w[b], wdy = ky.w[b] * (b - ky.fx) * dx;
        const std::size_t row = static_cast<std::size_t>(ky.base + b) * nx;
        double sx = 0, sy = 0, sdx = 0, sdy = 0, tx = 0, ty = 0;
        for (int a = 0; a < 3; ++a) {
          const std::size_t n = row + col[kx.base + 1 + a];
          const Node& node = nodes[n];
          sx += kx.w[a] * node.vx, sy += kx.w[a] * node.vy;
          sdx += wdx[a] * node.vx, sdy += wdx[a] * node.vy;
          if constexpr (kExact) tx += kx.dw[a] * node.vx, ty += kx.dw[a] * node.vy;
          if constexpr (!kApic) {
            ox += kx.w[a] * wy * g.arrays.mx[n];
            oy += kx.w[a] * wy * g.arrays.my[n];
          }
        }
        vx += wy * sx, vy += wy * sy;
        bxx += wy * sdx, bxy += wdy * sx;
        byx += wy * sdy, byy += wdy * sy;
        if constexpr (kExact) {  // grad w = (dw_a w_b, w_a dw_b) / dx
          gxx += wy * tx, gxy += ky.dw[b] * sx;
          gyx += wy * ty, gyy += ky.dw[b] * sy;
        }
      }
      const Mat2 c{bxx * c_scale, bxy * c_scale, byx * c_scale, byy * c_scale};
      P.C[p] = c;
      if constexpr (kApic) {
        P.vx[p] = vx, P.vy[p] = vy;
      } else {
        P.vx[p] = alpha * (P.vx[p] + vx - ox) + (1.0 - alpha) * vx;
        P.vy[p] = alpha * (P.vy[p] + vy - oy) + (1.0 - alpha) * vy;
      }
      double x = P.x[p] + dt * vx;
      const double y = P.y[p] + dt * vy;
      if (periodic) x = x >= width ? x - width : (x < 0.0 ? x + width : x);
      P.x[p] = x, P.y[p] = y;

      const Mat2 grad =
          kExact ? Mat2{gxx * inv_dx, gxy * inv_dx, gyx * inv_dx, gyy * inv_dx} : c;
      const Mat2& f = P.Fe[p];  // trial Fe = (I + dt grad v) Fe
      blk.fxx[i] = f.xx + dt * (grad.xx * f.xx + grad.xy * f.yx);
      blk.fxy[i] = f.xy + dt * (grad.xx * f.xy + grad.xy * f.yy);
      blk.fyx[i] = f.yx + dt * (grad.yx * f.xx + grad.yy * f.yx);
      blk.fyy[i] = f.yy + dt * (grad.yx * f.xy + grad.yy * f.yy);

      const double v2 = P.vx[p] * P.vx[p] + P.vy[p] * P.vy[p];
      m.max_v2 = std::isnan(v2) ? v2 : std::max(m.max_v2, v2);  // NaN sticks
      m.y_min = std::min(m.y_min, y), m.y_max = std::max(m.y_max, y);
      m.x_min = std::min(m.x_min, x), m.x_max = std::max(m.x_max, x);
    }
    return_map_block(blk, nb, s.material);  // vectorised across the block
    for (std::size_t i = 0; i < nb; ++i) {
      const std::size_t p = b0 + i;
      Mat2& f = P.Fe[p];
      double plastic;
      if (blk.redo[i] != 0.0) [[unlikely]] {  // outside the series' range: the exact update
        f = Mat2{blk.fxx[i], blk.fxy[i], blk.fyx[i], blk.fyy[i]};
        plastic = return_map(f, s.material, P.tau[p]);
        if (std::isnan(plastic)) m.bad_jacobian = true;
      } else {
        f = Mat2{blk.exx[i], blk.exy[i], blk.eyx[i], blk.eyy[i]};
        P.tau[p] = Sym2{blk.txx[i], blk.txy[i], blk.tyy[i]};
        plastic = blk.plastic[i];
      }
      P.dep[p] += plastic;  // ep, the running total, is updated once per frame
    }
  }
  return m;
}

StepMeasure combine(const StepMeasure& a, const StepMeasure& b) {
  StepMeasure m;
  m.max_v2 = std::isnan(a.max_v2) || std::isnan(b.max_v2) ? std::nan("")
                                                           : std::max(a.max_v2, b.max_v2);
  m.y_min = std::min(a.y_min, b.y_min), m.y_max = std::max(a.y_max, b.y_max);
  m.x_min = std::min(a.x_min, b.x_min), m.x_max = std::max(a.x_max, b.x_max);
  m.bad_jacobian = a.bad_jacobian || b.bad_jacobian;
  return m;
}

}  // namespace

void g2p(State& s, double dt, ThreadPool& pool) {
  std::vector<StepMeasure>& parts = s.partial_measures;  // sized once, one per thread
  const std::size_t n = s.particles.n;
  const bool apic = s.setup.transfer == Transfer::apic;
  const bool exact = s.setup.gradient == Gradient::bspline;
  pool.run([&](int t) {
    const std::size_t b = pool.begin(n, t), e = pool.end(n, t);
    Particles& P = s.particles;
    const Grid& g = s.grid;
    if (apic && !exact) parts[t] = gather<true, false>(P, s.setup, g, b, e, dt);
    else if (apic) parts[t] = gather<true, true>(P, s.setup, g, b, e, dt);
    else if (!exact) parts[t] = gather<false, false>(P, s.setup, g, b, e, dt);
    else parts[t] = gather<false, true>(P, s.setup, g, b, e, dt);
  });
  StepMeasure m = parts[0];
  for (std::size_t t = 1; t < parts.size(); ++t) m = combine(m, parts[t]);
  s.measure = m;
}


}  // namespace compaction
