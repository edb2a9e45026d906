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
// then scatters each particle-node pair into the node's first or second field.
// With threads, each scatters a share of the particles: into the grid where its rows are its
// own, else into its scratch arrays, summed into the grid afterwards (scatter_rows.hpp).
#include <algorithm>
#include <cstring>

#include "kernel.hpp"
#include "pore_contact.hpp"
#include "simd_dispatch.hpp"
#include "stages.hpp"

namespace compaction {

namespace {

// Where a thread's scatter goes: a particle whose stencil rows are `alone` (scatter_rows.hpp)
// into the grid's arrays, any other into `own`; alone = null sends everything to the grid.
// split_fields also writes each particle's field bits (Particles::field_bits) for g2p.
struct Targets {
  NodeArrays* grid;
  NodeArrays* own;
  const std::uint8_t* alone;
  std::uint16_t* field_bits;
  // Whether a particle whose stencil starts at row `base` goes into `own`.
  bool to_own(int base) const { return alone != nullptr && !alone[base]; }
};

// Zeroes nodes [lo, hi) (and their second field) and the rows' other arrays, where a scene has
// them.
void clear_nodes(const Grid& g, NodeArrays& a, std::size_t lo, std::size_t hi) {
  std::fill(a.nodes.begin() + lo, a.nodes.begin() + hi, Node{0, 0, 0, 0});
  if (g.field2 != 0) {
    std::fill(a.nodes.begin() + g.field2 + lo, a.nodes.begin() + g.field2 + hi, Node{0, 0, 0, 0});
  }
  for (std::vector<double>* v : {&a.mx, &a.my}) {
    if (!v->empty()) std::fill(v->begin() + lo, v->begin() + hi, 0.0);
  }
  if (!a.normal.empty()) std::fill(a.normal.begin() + lo, a.normal.begin() + hi, NodeNormal{0, 0});
}

// Zeroes thread t's scratch on the rows it may write there: those near a shared row.
void clear_near_rows(const Grid& g, NodeArrays& a, const ScatterRows& rows, int t) {
  const int lo = std::max(rows.lo[t], g.row_lo), hi = std::min(rows.hi[t], g.row_hi);
  for (int r = lo; r < hi; ++r) {
    if (!rows.near[r]) continue;
    const std::size_t i = static_cast<std::size_t>(r) * g.nx;
    clear_nodes(g, a, i, i + g.nx);
  }
}

// Adds the threads' scratch into the grid on rows [row_begin, row_end), thread 1 first: the
// nodes (both fields, and pic_flip's momenta) or, with `normals`, the node normals.
void sum_scratch(Grid& g, int row_begin, int row_end, bool normals) {
  const ScatterRows& rows = g.scatter_rows;
  for (int r = row_begin; r < row_end; ++r) {
    if (!rows.near[r]) continue;
    const std::size_t b = static_cast<std::size_t>(r) * g.nx, e = b + g.nx;
    for (std::size_t u = 0; u < g.scratch.size(); ++u) {
      if (!rows.reaches(static_cast<int>(u) + 1, r)) continue;
      const NodeArrays& src = g.scratch[u];
      NodeArrays& dst = g.arrays;
      if (normals) {
        for (std::size_t i = b; i < e; ++i) {
          dst.normal[i].x += src.normal[i].x, dst.normal[i].y += src.normal[i].y;
        }
        continue;
      }
      for (std::size_t f = 0; f <= (g.field2 != 0 ? 1u : 0u); ++f) {
        for (std::size_t i = b + f * g.field2; i < e + f * g.field2; ++i) {
          Node& d = dst.nodes[i];
          d.m += src.nodes[i].m, d.vx += src.nodes[i].vx, d.vy += src.nodes[i].vy;
        }
      }
      if (!dst.mx.empty()) {
        for (std::size_t i = b; i < e; ++i) dst.mx[i] += src.mx[i], dst.my[i] += src.my[i];
      }
    }
  }
}

// The four doubles of a Node, {m, m vx, m vy, 0}, as one vector (GCC vector extension): one
// AVX2 operation. The baseline copy adds the lanes one by one instead: SSE2 would split the
// vector through the stack, which makes the scatter several times slower.
using Lanes = double __attribute__((vector_size(32)));
static_assert(sizeof(Lanes) == sizeof(Node));

// The order in which a block's particles add to the nodes: particle k of the block's first
// half, then particle k of its second half, and so on. Neighbours in the lattice order share
// most of their nine nodes, so each node update would wait for the previous particle's store
// to that node; particles half a block apart (8 cells along a lattice row) rarely share one.
// Every node still gets its particles' contributions in one fixed order, so the result bits
// depend only on the blocks. (The node normals of split_fields keep the lattice order: a
// pair's field is the sign of a product with its node's normal, and on the rows a thread has
// to itself that normal then has the same bits with one thread as with two.)
inline std::size_t interleaved(std::size_t kk, std::size_t nb) {
  return (kk & 1) != 0 ? (nb + 1) / 2 + kk / 2 : kk / 2;
}

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
  alignas(64) std::int64_t bits[n];             // split_fields: the field of each pair
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

// split_fields: the field of each pair of the block's particles and their stencil nodes, bit
// 3 b + a set when the particle's normal opposes node (a, b)'s (pore_contact::second_field), as
// a loop across the block that vectorises (the node normals gathered).
[[gnu::always_inline]] inline void choose_fields_block(
    std::size_t n, std::ptrdiff_t nx, const NodeNormal* __restrict normals,
    const double* __restrict pnx, const double* __restrict pny, ScatterBlock* __restrict sb) {
  for (std::size_t i = 0; i < n; ++i) {
    const double px = pnx[i], py = pny[i];
    const std::ptrdiff_t cs[3] = {sb->cols[0][i], sb->cols[1][i], sb->cols[2][i]};
    std::int64_t bits = 0;
#pragma GCC unroll 3
    for (int b = 0; b < 3; ++b) {
      const std::ptrdiff_t row = sb->row0[i] + b * nx;
#pragma GCC unroll 3
      for (int a = 0; a < 3; ++a) {
        const NodeNormal m = normals[row + cs[a]];
        bits |= static_cast<std::int64_t>(pore_contact::second_field(px, py, m.x, m.y))
                << (3 * b + a);
      }
    }
    sb->bits[i] = bits;
  }
}

// The scatter of particles [begin, end) into `out`, one block at a time (run_loop in
// simd_dispatch.hpp makes its variants and copies). The AVX2 copy updates a node as Lanes.
// kSplit: a pair whose particle normal opposes the node's goes into the second field.
template <bool kApic, bool kExact, bool kSplit = false>
struct Scatter {
  template <bool kAvx2>
  [[gnu::always_inline]] static void run(const Particles& P, const Setup& s, const Grid& g,
                                         Targets to, std::size_t begin, std::size_t end,
                                         double dt) {
    const std::ptrdiff_t nx = g.nx;
    Node* const grid_nodes = to.grid->nodes.data();
    Node* const own_nodes = to.own->nodes.data();
    double* const mxy[2][2] = {{to.grid->mx.data(), to.grid->my.data()},
                               {to.own->mx.data(), to.own->my.data()}};
    [[maybe_unused]] const NodeNormal* const normals = g.arrays.normal.data();
    [[maybe_unused]] const std::ptrdiff_t field2 = static_cast<std::ptrdiff_t>(g.field2);
    ScatterBlock sb;
    for (std::size_t b0 = begin; b0 < end; b0 += kScatterBlock) {
      const std::size_t nb = std::min(kScatterBlock, end - b0);
      prepare_block<kApic, kExact>(
          nb, dt, s, g, P.mass, P.x.data() + b0, P.y.data() + b0, P.vx.data() + b0,
          P.vy.data() + b0, P.C.xx.data() + b0, P.C.xy.data() + b0, P.C.yx.data() + b0,
          P.C.yy.data() + b0, P.tau.xx.data() + b0, P.tau.xy.data() + b0, P.tau.yy.data() + b0,
          &sb);
      if constexpr (kSplit) {
        choose_fields_block(nb, nx, normals, P.nx.data() + b0, P.ny.data() + b0, &sb);
      }
      for (std::size_t kk = 0; kk < nb; ++kk) {
        const std::size_t k = interleaved(kk, nb);
        const bool own = to.to_own(sb.base[k]);
        Node* const nodes = own ? own_nodes : grid_nodes;
        [[maybe_unused]] double* const mx = mxy[own][0];
        [[maybe_unused]] double* const my = mxy[own][1];
        const std::ptrdiff_t cs[3] = {sb.cols[0][k], sb.cols[1][k], sb.cols[2][k]};
        [[maybe_unused]] std::int64_t bits = 0;
        if constexpr (kSplit) bits = sb.bits[k];
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
            if constexpr (kSplit) i += -((bits >> (3 * b + a)) & 1) & field2;
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
              mx[i] += wa * sb.wy[b][k] * sb.mvx[k];
              my[i] += wa * sb.wy[b][k] * sb.mvy[k];
            }
          }
        }
        if constexpr (kSplit) to.field_bits[b0 + k] = static_cast<std::uint16_t>(bits);
      }
    }
  }
};

// The node normals of split_fields: sum of w_ip n_p (pore_contact.hpp), particles [begin, end),
// a block at a time: the weights and node columns vectorised across the block, then each
// particle's nine nodes (run_variant makes the baseline and the AVX2 copy).
struct ScatterNormals {
  static constexpr std::size_t n = kScatterBlock;
  struct Block {
    alignas(64) double wx[3][n], wy[3][n];
    alignas(64) std::ptrdiff_t cols[3][n], row0[n];
    alignas(64) int base[n];
  };
  template <bool kAvx2>
  [[gnu::always_inline]] static void run(const Particles& P, const Grid& g, const Targets& to,
                                         std::size_t begin, std::size_t end) {
    const double inv_dx = g.inv_dx, gxo = g.gx, gyo = g.gy;
    const std::ptrdiff_t nx = g.nx;
    const int* __restrict col = g.col.data();
    const double* __restrict px = P.x.data();
    const double* __restrict py = P.y.data();
    Block blk;
    for (std::size_t b0 = begin; b0 < end; b0 += n) {
      const std::size_t nb = std::min(n, end - b0);
      Block* __restrict bk = &blk;
      for (std::size_t i = 0; i < nb; ++i) {
        const auto kx = kernel::quadratic(px[b0 + i] * inv_dx + gxo);
        const auto ky = kernel::quadratic(py[b0 + i] * inv_dx + gyo);
#pragma GCC unroll 3
        for (int a = 0; a < 3; ++a) {
          bk->wx[a][i] = kx.w[a], bk->wy[a][i] = ky.w[a];
          bk->cols[a][i] = col[kx.base + 1 + a];
        }
        bk->row0[i] = ky.base * nx;
        bk->base[i] = ky.base;
      }
      for (std::size_t k = 0; k < nb; ++k) {
        NodeNormal* const out = (to.to_own(blk.base[k]) ? to.own : to.grid)->normal.data();
        const double pnx = P.nx[b0 + k], pny = P.ny[b0 + k];
#pragma GCC unroll 3
        for (int b = 0; b < 3; ++b) {
          const std::ptrdiff_t row = blk.row0[k] + b * nx;
#pragma GCC unroll 3
          for (int a = 0; a < 3; ++a) {
            NodeNormal& m = out[row + blk.cols[a][k]];
            const double w = blk.wx[a][k] * blk.wy[b][k];
            m.x += w * pnx;
            m.y += w * pny;
          }
        }
      }
    }
  }
};

}  // namespace

void p2g(State& s, double dt, ThreadPool& pool) {
  Grid& g = s.grid;
  const Particles& P = s.particles;
  const bool split = s.setup.split_fields;  // apic and mls (validate())
  const bool threads = pool.size() > 1;
  const std::size_t n = P.n;
  ScatterRows& rows = g.scatter_rows;
  const std::size_t lo = static_cast<std::size_t>(g.row_lo) * g.nx;
  const std::size_t count = static_cast<std::size_t>(g.row_hi - g.row_lo) * g.nx;
  const int row_count = g.row_hi - g.row_lo;
  std::uint16_t* bits = s.particles.field_bits.data();
  auto targets = [&](int t) {
    return t == 0 ? Targets{&g.arrays, &g.arrays, nullptr, bits}
                  : Targets{&g.arrays, &g.scratch[t - 1], rows.alone.data(), bits};
  };
  // 1. The grid's rows zeroed, a share each; the rows each thread's particles reach.
  pool.run([&](int t) {
    clear_nodes(g, g.arrays, lo + pool.begin(count, t), lo + pool.end(count, t));
    if (threads) stencil_rows(P.y.data(), pool.begin(n, t), pool.end(n, t), g.inv_dx, g.gy, rows.lo[t], rows.hi[t]);
  });
  if (threads) rows.plan(g.row_lo, g.row_hi);
  // 2. split_fields: the node normals, which pick the field of each particle-node pair.
  if (split) {
    pool.run([&](int t) {
      if (t > 0) clear_near_rows(g, g.scratch[t - 1], rows, t);
      const Targets to = targets(t);
      run_variant<ScatterNormals>(P, g, to, pool.begin(n, t), pool.end(n, t));
    });
    if (threads) {
      pool.run([&](int t) {
        sum_scratch(g, g.row_lo + static_cast<int>(pool.begin(row_count, t)),
                    g.row_lo + static_cast<int>(pool.end(row_count, t)), true);
      });
    }
  }
  // 3. Mass and momentum, then the threads' scratch summed in, in a fixed order (thread 1,
  // 2, ...), so that results do not depend on timing.
  pool.run([&](int t) {
    if (t > 0 && !split) clear_near_rows(g, g.scratch[t - 1], rows, t);
    const std::size_t b = pool.begin(n, t), e = pool.end(n, t);
    const Targets to = targets(t);
    if (split) {
      run_variant<Scatter<true, false, true>>(P, s.setup, g, to, b, e, dt);
    } else {
      run_loop<Scatter>(s.setup.transfer, s.setup.gradient, P, s.setup, g, to, b, e, dt);
    }
  });
  if (!threads) return;
  pool.run([&](int t) {
    sum_scratch(g, g.row_lo + static_cast<int>(pool.begin(row_count, t)),
                g.row_lo + static_cast<int>(pool.end(row_count, t)), false);
  });
}

}  // namespace compaction
