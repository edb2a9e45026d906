// One block of particles' share of the P2G scatter (p2g.cpp, p2g_split_fields.cpp): what each
// particle brings to its 3 x 3 nodes, computed across the block so that it vectorises, and the
// update of one node by one particle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "kernel.hpp"
#include "state.hpp"

namespace compaction {

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
  alignas(64) std::ptrdiff_t cols[3][n], row0[n];  // the stencil's node columns, first node row
  alignas(64) int base[n];                      // first stencil row
  alignas(64) double wx[3][n], wdx[3][n];       // x-weights, x-weighted offsets
  alignas(64) double wm[3][n], qx[3][n], qy[3][n], qxx[3][n], qyx[3][n];  // per stencil row
  alignas(64) double wy[3][n], dwx[3][n], dwy[3][n];  // bspline, pic_flip only
  alignas(64) double sxx[n], sxy[n], syy[n], mvx[n], mvy[n];
  alignas(64) std::int64_t outside[n];          // split_fields: the normal's outside windows
};

// The per-particle part of the scatter for one block: arithmetic only, vectorised across it.
template <bool kApic, bool kExact>
[[gnu::always_inline]] inline void prepare_block(
    std::size_t n, double dt, const Setup& s, const Grid& g, double m,
    const double* __restrict px, const double* __restrict py, const double* __restrict pvx,
    const double* __restrict pvy, const double* __restrict cxx, const double* __restrict cxy,
    const double* __restrict cyx, const double* __restrict cyy, const double* __restrict txx,
    const double* __restrict txy, const double* __restrict tyy, ScatterBlock* __restrict sb) {
  const double dx = g.dx, inv_dx = g.inv_dx, gxo = g.gx, gyo = g.gy;
  const std::ptrdiff_t nx = g.nx;
  const int* __restrict col = g.col.data();  // a stencil column's node column (periodic wrap)
  const double stress = kExact ? 0.0 : -dt * s.scale;
  const double impulse = -dt * s.vol0 * inv_dx;  // exact gradient: dw is per grid cell
  for (std::size_t i = 0; i < n; ++i) {
    const auto kx = kernel::quadratic(px[i] * inv_dx + gxo);
    const auto ky = kernel::quadratic(py[i] * inv_dx + gyo);
    const Sym2 t{txx[i], txy[i], tyy[i]};
    Mat2 q{stress * t.xx, stress * t.xy, stress * t.xy, stress * t.yy};
    if constexpr (kApic) {
      q.xx += m * cxx[i], q.xy += m * cxy[i], q.yx += m * cyx[i], q.yy += m * cyy[i];
    }
    const double mvx = m * pvx[i], mvy = m * pvy[i];
#pragma GCC unroll 3
    for (int a = 0; a < 3; ++a) sb->cols[a][i] = col[kx.base + 1 + a];
    sb->row0[i] = ky.base * nx;
    sb->base[i] = ky.base;
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

// Node n += wa lo + wd hi, lanes {m, m vx, m vy}: one Lanes operation in the AVX2 copy (the zero
// lanes add exact zeros, so it rounds each lane as the scalar update does).
template <bool kAvx2>
[[gnu::always_inline]] inline void add_to_node(Node& n, double wa, double wd, const double (&lo)[4],
                                               const double (&hi)[4]) {
  if constexpr (kAvx2) {
    Lanes v;
    std::memcpy(&v, &n, sizeof v);
    v += wa * Lanes{lo[0], lo[1], lo[2], lo[3]} + wd * Lanes{hi[0], hi[1], hi[2], hi[3]};
    std::memcpy(&n, &v, sizeof v);
  } else {
    n.m += wa * lo[0];
    n.vx += wa * lo[1] + wd * hi[1];
    n.vy += wa * lo[2] + wd * hi[2];
  }
}

}  // namespace compaction
