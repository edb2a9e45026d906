// Particle to grid transfer (APIC / MLS-MPM, Hu et al. 2018, Eq. 29; Jiang et al. 2015).
//
// For each particle p and stencil node i (weight w, offset d = x_i - x_p):
//   m_i += w m_p
//   (m v)_i += w (m_p v_p + Q_p d),  Q_p = -dt V0 D^-1 tau_p + m_p C_p   (apic)
// pic_flip keeps the momentum m_p v_p apart (mx, my) so the grid update can form v_old, and
// drops the affine part m_p C_p from Q. gradient = bspline takes the stress out of Q and adds
// the standard MPM force impulse -dt V0 tau_p grad w_ip with the exact B-spline gradient.
// Particles go in blocks of kScatterBlock: their coefficients first (vectorised across the
// block), then their node updates (simd_dispatch.hpp: a baseline and an AVX2 copy).
// pore_contact = split_fields (pore_contact.hpp) first sums the particles' normals on the nodes,
// then scatters each particle-node pair into the node's first or second field, on one thread.
#include <algorithm>
#include <cstring>

#include "kernel.hpp"
#include "pore_contact.hpp"
#include "simd_dispatch.hpp"
#include "stages.hpp"

namespace compaction {

namespace {

void clear_rows(const Grid& g, NodeArrays& a, bool flip) {
  const std::size_t lo = static_cast<std::size_t>(g.row_lo) * g.nx;
  const std::size_t hi = static_cast<std::size_t>(g.row_hi) * g.nx;
  std::fill(a.nodes.begin() + lo, a.nodes.begin() + hi, Node{0, 0, 0, 0});
  if (flip) {
    std::fill(a.mx.begin() + lo, a.mx.begin() + hi, 0.0);
    std::fill(a.my.begin() + lo, a.my.begin() + hi, 0.0);
  }
}

// The four doubles of a Node, {m, m vx, m vy, 0}, as one vector (GCC vector extension): one
// AVX2 operation. The baseline copy adds the lanes one by one instead: SSE2 would split the
// vector through the stack, which makes the scatter several times slower.
using Lanes = double __attribute__((vector_size(32)));
static_assert(sizeof(Lanes) == sizeof(Node));

// What a block of particles brings to its 3 x 3 nodes, structure of arrays: node (a, b) of
// particle i gets wx_a * lo_b + wdx_a * hi_b with lo_b = {wm_b, qx_b, qy_b, 0} and
// hi_b = {0, qxx_b, qyx_b, 0} (plus the exact-gradient and FLIP terms of those variants).
constexpr std::size_t kScatterBlock = 32;
struct ScatterBlock {
  static constexpr std::size_t n = kScatterBlock;
  alignas(64) std::ptrdiff_t col0[n], row0[n];  // first stencil column (into col) and row
  alignas(64) double wx[3][n], wdx[3][n];       // x-weights, x-weighted offsets
  alignas(64) double wm[3][n], qx[3][n], qy[3][n], qxx[3][n], qyx[3][n];  // per stencil row
  alignas(64) double wy[3][n], dwx[3][n], dwy[3][n];  // bspline, pic_flip only
  alignas(64) double sxx[n], sxy[n], syy[n], mvx[n], mvy[n];
};

// The per-particle part of the scatter for one block: arithmetic only, vectorised across it.
template <bool kApic, bool kExact>
[[gnu::always_inline]] inline void prepare_block(
    std::size_t n, double dt, const Setup& s, const Grid& g, double m,
    const double* __restrict px, const double* __restrict py, const double* __restrict pvx,
    const double* __restrict pvy, const Mat2* __restrict pc, const Sym2* __restrict ptau,
    ScatterBlock* __restrict sb) {
  const double dx = g.dx, inv_dx = g.inv_dx, gxo = g.gx, gyo = g.gy;
  const std::ptrdiff_t nx = g.nx;
  const double stress = kExact ? 0.0 : -dt * s.scale;
  const double impulse = -dt * s.vol0 * inv_dx;  // exact gradient: dw is per grid cell
  for (std::size_t i = 0; i < n; ++i) {
    const auto kx = kernel::quadratic(px[i] * inv_dx + gxo);
    const auto ky = kernel::quadratic(py[i] * inv_dx + gyo);
    const Sym2 t = ptau[i];
    Mat2 q{stress * t.xx, stress * t.xy, stress * t.xy, stress * t.yy};
    if constexpr (kApic) {
      const Mat2 c = pc[i];
      q.xx += m * c.xx, q.xy += m * c.xy, q.yx += m * c.yx, q.yy += m * c.yy;
    }
    const double mvx = m * pvx[i], mvy = m * pvy[i];
    sb->col0[i] = kx.base + 1;
    sb->row0[i] = ky.base * nx;
    // Node (a, b) gets wx_a wy_b (m v + Q d), d = (dx_a, dy_b): the x-weights and x-weighted
    // offsets are formed once, each row then adds its y-part.
#pragma GCC unroll 3
    for (int a = 0; a < 3; ++a) {
      sb->wx[a][i] = kx.w[a];
      sb->wdx[a][i] = kx.w[a] * (a - kx.fx) * dx;
    }
#pragma GCC unroll 3
    for (int b = 0; b < 3; ++b) {
      const double wy = ky.w[b], dy = (b - ky.fx) * dx;
      sb->qx[b][i] = wy * (mvx + q.xy * dy), sb->qy[b][i] = wy * (mvy + q.yy * dy);
      sb->wm[b][i] = wy * m, sb->qxx[b][i] = wy * q.xx, sb->qyx[b][i] = wy * q.yx;
      if constexpr (kExact || !kApic) sb->wy[b][i] = wy;
      if constexpr (kExact) sb->dwx[b][i] = kx.dw[b], sb->dwy[b][i] = ky.dw[b];
    }
    if constexpr (kExact) {
      sb->sxx[i] = impulse * t.xx, sb->sxy[i] = impulse * t.xy, sb->syy[i] = impulse * t.yy;
    }
    if constexpr (!kApic) sb->mvx[i] = mvx, sb->mvy[i] = mvy;
  }
}

// The scatter of particles [begin, end) into `out`, one block at a time (run_loop in
// simd_dispatch.hpp makes its variants and copies). The AVX2 copy updates a node as Lanes.
// kSplit: a pair whose particle normal opposes the node's goes into the second field.
template <bool kApic, bool kExact, bool kSplit = false>
struct Scatter {
  template <bool kAvx2>
  [[gnu::always_inline]] static void run(const Particles& P, const Setup& s, const Grid& g,
                                         NodeArrays& out, std::size_t begin, std::size_t end,
                                         double dt) {
    const std::ptrdiff_t nx = g.nx;
    const int* col = g.col.data();
    Node* nodes = out.nodes.data();
    ScatterBlock sb;
    for (std::size_t b0 = begin; b0 < end; b0 += kScatterBlock) {
      const std::size_t nb = std::min(kScatterBlock, end - b0);
      prepare_block<kApic, kExact>(nb, dt, s, g, P.mass, P.x.data() + b0, P.y.data() + b0,
                                   P.vx.data() + b0, P.vy.data() + b0, P.C.data() + b0,
                                   P.tau.data() + b0, &sb);
      for (std::size_t k = 0; k < nb; ++k) {
        const std::ptrdiff_t cs[3] = {col[sb.col0[k]], col[sb.col0[k] + 1], col[sb.col0[k] + 2]};
#pragma GCC unroll 3
        for (int b = 0; b < 3; ++b) {
          const std::ptrdiff_t row = sb.row0[k] + b * nx;
          // The zero lanes add exact zeros, so the wide update rounds each lane as the scalar
          // one does.
          const double lo[4] = {sb.wm[b][k], sb.qx[b][k], sb.qy[b][k], 0.0};
          const double hi[4] = {0.0, sb.qxx[b][k], sb.qyx[b][k], 0.0};
#pragma GCC unroll 3
          for (int a = 0; a < 3; ++a) {
            std::ptrdiff_t i = row + cs[a];
            const double wa = sb.wx[a][k], wd = sb.wdx[a][k];
            if constexpr (kSplit) {
              const std::size_t p = b0 + k;
              const bool second = pore_contact::second_field(P.nx[p], P.ny[p], g.nnx[i], g.nny[i]);
              i += second ? static_cast<std::ptrdiff_t>(g.field2) : 0;
            }
            if constexpr (kAvx2) {
              Lanes n;
              std::memcpy(&n, &nodes[i], sizeof n);
              n += wa * Lanes{lo[0], lo[1], lo[2], lo[3]} + wd * Lanes{hi[0], hi[1], hi[2], hi[3]};
              std::memcpy(&nodes[i], &n, sizeof n);
            } else {
              Node& n = nodes[i];
              n.m += wa * lo[0];
              n.vx += wa * lo[1] + wd * hi[1];
              n.vy += wa * lo[2] + wd * hi[2];
            }
            if constexpr (kExact) {  // -dt V0 tau grad w, grad w = (dw_a w_b, w_a dw_b) / dx
              const double gx = sb.dwx[a][k] * sb.wy[b][k], gy = wa * sb.dwy[b][k];
              nodes[i].vx += sb.sxx[k] * gx + sb.sxy[k] * gy;
              nodes[i].vy += sb.sxy[k] * gx + sb.syy[k] * gy;
            }
            if constexpr (!kApic) {
              out.mx[i] += wa * sb.wy[b][k] * sb.mvx[k];
              out.my[i] += wa * sb.wy[b][k] * sb.mvy[k];
            }
          }
        }
      }
    }
  }
};

// The node normals of split_fields: sum of w_ip n_p (pore_contact.hpp).
void scatter_normals(const Particles& P, Grid& g) {
  const std::size_t lo = static_cast<std::size_t>(g.row_lo) * g.nx;
  const std::size_t hi = static_cast<std::size_t>(g.row_hi) * g.nx;
  std::fill(g.nnx.begin() + lo, g.nnx.begin() + hi, 0.0);
  std::fill(g.nny.begin() + lo, g.nny.begin() + hi, 0.0);
  const double gxo = g.gx, gyo = g.gy;
  for (std::size_t p = 0; p < P.n; ++p) {
    const auto kx = kernel::quadratic(P.x[p] * g.inv_dx + gxo);
    const auto ky = kernel::quadratic(P.y[p] * g.inv_dx + gyo);
    for (int b = 0; b < 3; ++b) {
      const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(ky.base + b) * g.nx;
      for (int a = 0; a < 3; ++a) {
        const std::ptrdiff_t i = row + g.col[kx.base + 1 + a];
        const double w = kx.w[a] * ky.w[b];
        g.nnx[i] += w * P.nx[p];
        g.nny[i] += w * P.ny[p];
      }
    }
  }
}

}  // namespace

void p2g(State& s, double dt, ThreadPool& pool) {
  Grid& g = s.grid;
  const bool apic = s.setup.transfer == Transfer::apic;
  const std::size_t n = s.particles.n;
  if (s.setup.split_fields) {  // apic and mls (validate()); one thread
    clear_rows(g, g.arrays, false);
    const std::size_t lo = static_cast<std::size_t>(g.row_lo) * g.nx + g.field2;
    const std::size_t hi = static_cast<std::size_t>(g.row_hi) * g.nx + g.field2;
    std::fill(g.arrays.nodes.begin() + lo, g.arrays.nodes.begin() + hi, Node{0, 0, 0, 0});
    scatter_normals(s.particles, g);
    run_variant<Scatter<true, false, true>>(s.particles, s.setup, g, g.arrays, std::size_t{0},
                                            n, dt);
    return;
  }
  pool.run([&](int t) {
    NodeArrays& out = t == 0 ? g.arrays : g.scratch[t - 1];
    clear_rows(g, out, !apic);
    const std::size_t b = pool.begin(n, t), e = pool.end(n, t);
    run_loop<Scatter>(s.setup.transfer, s.setup.gradient, s.particles, s.setup, g, out, b, e, dt);
  });
  if (pool.size() == 1) return;
  // Sum the threads' arrays into the grid, each thread a share of the rows, in a fixed order
  // (thread 1, 2, ...) so that results do not depend on timing.
  const std::size_t lo = static_cast<std::size_t>(g.row_lo) * g.nx;
  const std::size_t count = static_cast<std::size_t>(g.row_hi - g.row_lo) * g.nx;
  pool.run([&](int t) {
    const std::size_t b = lo + pool.begin(count, t), e = lo + pool.end(count, t);
    for (const NodeArrays& src : g.scratch) {
      for (std::size_t i = b; i < e; ++i) {
        Node& d = g.arrays.nodes[i];
        d.m += src.nodes[i].m, d.vx += src.nodes[i].vx, d.vy += src.nodes[i].vy;
      }
      if (!apic) {
        for (std::size_t i = b; i < e; ++i) {
          g.arrays.mx[i] += src.mx[i];
          g.arrays.my[i] += src.my[i];
        }
      }
    }
  });
}

}  // namespace compaction
