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
// pore_contact = split_fields (pore_contact.hpp) scatters one field and which windows the normals
// lie outside of, then splits the nodes where two fields may differ from one
// (p2g_split_fields.cpp).
// With threads, each scatters a share of the particles: into the grid where its rows are its
// own, else into its scratch arrays, summed into the grid afterwards (scatter_rows.hpp).
#include <algorithm>
#include <cstring>

#include "kernel.hpp"
#include "p2g_split_fields.hpp"
#include "pore_contact.hpp"
#include "scatter_block.hpp"
#include "simd_dispatch.hpp"
#include "stages.hpp"

namespace compaction {

namespace {

// Where a thread's scatter goes: a particle whose stencil rows are `alone` (scatter_rows.hpp)
// into the grid's arrays, any other into `own`; alone = null sends everything to the grid.
// split_fields also writes each particle's first stencil node into `first_node`.
struct Targets {
  NodeArrays* grid;
  NodeArrays* own;
  const std::uint8_t* alone;
  std::uint32_t* first_node;
  // Whether a particle whose stencil starts at row `base` goes into `own`.
  bool to_own(int base) const { return alone != nullptr && !alone[base]; }
};

// Zeroes nodes [lo, hi) (their first field: p2g_split_fields.cpp keeps the second) and the
// rows' other arrays, where a scene has them.
void clear_nodes(NodeArrays& a, std::size_t lo, std::size_t hi) {
  std::fill(a.nodes.begin() + lo, a.nodes.begin() + hi, Node{0, 0, 0, 0});
  for (std::vector<double>* v : {&a.mx, &a.my}) {
    if (!v->empty()) std::fill(v->begin() + lo, v->begin() + hi, 0.0);
  }
  if (!a.windows.empty()) std::fill(a.windows.begin() + lo, a.windows.begin() + hi, 0);
}

// Zeroes thread t's scratch on the rows it may write there: those near a shared row.
void clear_near_rows(const Grid& g, NodeArrays& a, const ScatterRows& rows, int t) {
  const int lo = std::max(rows.lo[t], g.row_lo), hi = std::min(rows.hi[t], g.row_hi);
  for (int r = lo; r < hi; ++r) {
    if (!rows.near[r]) continue;
    const std::size_t i = static_cast<std::size_t>(r) * g.nx;
    clear_nodes(a, i, i + g.nx);
  }
}

// Adds the threads' scratch into the grid on rows [row_begin, row_end), thread 1 first: the
// nodes, pic_flip's momenta and split_fields' windows (or'ed).
void sum_scratch(Grid& g, int row_begin, int row_end) {
  const ScatterRows& rows = g.scatter_rows;
  for (int r = row_begin; r < row_end; ++r) {
    if (!rows.near[r]) continue;
    const std::size_t b = static_cast<std::size_t>(r) * g.nx, e = b + g.nx;
    for (std::size_t u = 0; u < g.scratch.size(); ++u) {
      if (!rows.reaches(static_cast<int>(u) + 1, r)) continue;
      const NodeArrays& src = g.scratch[u];
      NodeArrays& dst = g.arrays;
      for (std::size_t i = b; i < e; ++i) {
        Node& d = dst.nodes[i];
        d.m += src.nodes[i].m, d.vx += src.nodes[i].vx, d.vy += src.nodes[i].vy;
      }
      if (!dst.mx.empty()) {
        for (std::size_t i = b; i < e; ++i) dst.mx[i] += src.mx[i], dst.my[i] += src.my[i];
      }
      if (!dst.windows.empty()) {
        for (std::size_t i = b; i < e; ++i) dst.windows[i] |= src.windows[i];
      }
    }
  }
}

// The order in which a block's particles add to the nodes: particle k of the block's first
// half, then particle k of its second half, and so on. Neighbours in the lattice order share
// most of their nine nodes, so each node update would wait for the previous particle's store
// to that node; particles half a block apart (8 cells along a lattice row) rarely share one.
// Every node still gets its particles' contributions in one fixed order, so the result bits
// depend only on the blocks.
inline std::size_t interleaved(std::size_t kk, std::size_t nb) {
  return (kk & 1) != 0 ? (nb + 1) / 2 + kk / 2 : kk / 2;
}

// split_fields: the windows that a block's particle normals lie outside of
// (pore_contact::outside_windows), a loop that vectorises.
[[gnu::always_inline]] inline void windows_block(std::size_t n, const double* __restrict pnx,
                                                 const double* __restrict pny,
                                                 ScatterBlock* __restrict sb) {
  for (std::size_t i = 0; i < n; ++i) {
    sb->outside[i] = pore_contact::outside_windows(pnx[i], pny[i]);
  }
}

// The scatter of particles [begin, end) into `out`, one block at a time (run_loop in
// simd_dispatch.hpp makes its variants and copies). The AVX2 copy updates a node as Lanes.
// kWindows (split_fields): the windows each particle's normal lies outside of are or'ed into its
// first stencil node's, and that node recorded (SplitNodes::first_node).
template <bool kApic, bool kExact, bool kWindows = false>
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
    std::uint8_t* const windows[2] = {to.grid->windows.data(), to.own->windows.data()};
    ScatterBlock sb;
    for (std::size_t b0 = begin; b0 < end; b0 += kScatterBlock) {
      const std::size_t nb = std::min(kScatterBlock, end - b0);
      prepare_block<kApic, kExact>(
          nb, dt, s, g, P.mass, P.x.data() + b0, P.y.data() + b0, P.vx.data() + b0,
          P.vy.data() + b0, P.C.xx.data() + b0, P.C.xy.data() + b0, P.C.yx.data() + b0,
          P.C.yy.data() + b0, P.tau.xx.data() + b0, P.tau.xy.data() + b0, P.tau.yy.data() + b0,
          &sb);
      if constexpr (kWindows) windows_block(nb, P.nx.data() + b0, P.ny.data() + b0, &sb);
      for (std::size_t kk = 0; kk < nb; ++kk) {
        const std::size_t k = interleaved(kk, nb);
        const bool own = to.to_own(sb.base[k]);
        Node* const nodes = own ? own_nodes : grid_nodes;
        [[maybe_unused]] double* const mx = mxy[own][0];
        [[maybe_unused]] double* const my = mxy[own][1];
        const std::ptrdiff_t cs[3] = {sb.cols[0][k], sb.cols[1][k], sb.cols[2][k]};
#pragma GCC unroll 3
        for (int b = 0; b < 3; ++b) {
          const std::ptrdiff_t row = sb.row0[k] + b * nx;
          const double lo[4] = {sb.wm[b][k], sb.qx[b][k], sb.qy[b][k], 0.0};
          const double hi[4] = {0.0, sb.qxx[b][k], sb.qyx[b][k], 0.0};
#pragma GCC unroll 3
          for (int a = 0; a < 3; ++a) {
            const std::ptrdiff_t i = row + cs[a];
            const double wa = sb.wx[a][k];
            add_to_node<kAvx2>(nodes[i], wa, sb.wdx[a][k], lo, hi);
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
        if constexpr (kWindows) {
          const std::ptrdiff_t first = sb.row0[k] + cs[0];
          windows[own][first] |= static_cast<std::uint8_t>(sb.outside[k]);
          to.first_node[b0 + k] = static_cast<std::uint32_t>(first);
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
  // 1. The grid's rows zeroed, a share each; the rows each thread's particles reach.
  pool.run([&](int t) {
    clear_nodes(g.arrays, lo + pool.begin(count, t), lo + pool.end(count, t));
    if (threads) stencil_rows(P.y.data(), pool.begin(n, t), pool.end(n, t), g.inv_dx, g.gy, rows.lo[t], rows.hi[t]);
  });
  if (threads) rows.plan(g.row_lo, g.row_hi);
  // 2. Mass and momentum (split_fields: and the normals' windows), then the threads' scratch
  // summed in, in a fixed order (thread 1, 2, ...), so that results do not depend on timing.
  pool.run([&](int t) {
    const std::size_t b = pool.begin(n, t), e = pool.end(n, t);
    std::uint32_t* const first = g.split.first_node.data();
    Targets to{&g.arrays, &g.arrays, nullptr, first};
    if (t > 0) {
      clear_near_rows(g, g.scratch[t - 1], rows, t);
      to = {&g.arrays, &g.scratch[t - 1], rows.alone.data(), first};
    }
    if (split) {
      run_variant<Scatter<true, false, true>>(P, s.setup, g, to, b, e, dt);
    } else {
      run_loop<Scatter>(s.setup.transfer, s.setup.gradient, P, s.setup, g, to, b, e, dt);
    }
  });
  if (threads) {
    pool.run([&](int t) {
      sum_scratch(g, g.row_lo + static_cast<int>(pool.begin(row_count, t)),
                  g.row_lo + static_cast<int>(pool.end(row_count, t)));
    });
  }
  // 3. split_fields: the nodes where two fields may differ from one, scattered again in two.
  if (split) split_fields(s, dt, pool);
}

}  // namespace compaction
