// Two velocity fields where they may differ from one (pore_contact.hpp), after p2g has scattered
// one field for every node:
//   1. last step's listed nodes are cleared (their second field, their flags) and its listed
//      particles' field bits zeroed;
//   2. the nodes to split are listed: mass below a full node's merge mass and normals that share
//      no window (pore_contact::may_oppose; p2g or'ed the windows each particle's normal lies
//      outside of into its first stencil node, so a node's are those of the nine first nodes
//      whose stencils hold it);
//   3. the particles whose stencil holds a listed node are listed, in the particles' order
//      (those whose first node reaches one);
//   4. the listed nodes' normals are summed from those particles, w_ip n_p;
//   5. the listed nodes' first fields are zeroed and the listed particles scattered into them
//      again, each pair into the field its normal picks (pore_contact::second_field), which its
//      field bits record for g2p.
// Every other node keeps its one field: its particles' normals share a window (within 90 degrees
// of each other) or it is full, so two fields would hold the same, or merge into the same.
// The listed nodes are a few percent of the grid, reached by a fifth to a third of the
// particles as pores close (bench/results/split_fields_listed.md).
// Threads list a share of the rows and of the particles each; steps 4 and 5 go by bands of
// rows (band_of), the even bands at once and then the odd ones, in the same order with any
// number of threads, so a listed node's fields have the same bits with any number of threads.
#include "p2g_split_fields.hpp"

#include <algorithm>
#include <vector>

#include "kernel.hpp"
#include "pore_contact.hpp"
#include "scatter_block.hpp"
#include "simd_dispatch.hpp"

namespace compaction {

namespace {

// A node is listed below this share of a full node's merge mass above it: p2g's one field sums
// its mass in another order than the two fields' sum that the grid update compares, so a node
// whose mass is the merge mass to round-off is listed (and then merged or not as two fields
// would be).
constexpr double kMergeMargin = 1e-9;

// Calls f(first) for the first nodes of the stencils that hold node k (a stencil's nodes are
// its first node's column and the two after it, periodic wrap or not, in its row and the two
// above), in rows from `row_floor` on.
template <class F>
void each_first_node(const Grid& g, std::size_t k, int row_floor, F&& f) {
  const int r = static_cast<int>(k / g.nx), i = static_cast<int>(k % g.nx);
  for (int b = 0; b < 3 && r - b >= row_floor; ++b) {
    const std::size_t row = static_cast<std::size_t>(r - b) * g.nx;
    for (int a = 0; a < 3; ++a) {
      int c = i - a;
      if (c < 0) {
        if (!g.periodic_x) break;
        c += g.nx;
      }
      f(row + c);
    }
  }
}

// Step 1: last step's listed nodes and particles cleared.
void clear_last(State& s) {
  Grid& g = s.grid;
  SplitNodes& sp = g.split;
  Node* const second = g.arrays.nodes.data() + g.field2;
  for (const std::uint32_t k : sp.nodes) {
    second[k] = Node{0, 0, 0, 0}, sp.node[k] = 0;
    each_first_node(g, k, 0, [&](std::size_t f) { sp.reach[f] = 0; });
  }
  sp.nodes.clear();
  for (const std::uint32_t p : sp.particles) s.particles.field_bits[p] = 0;
  sp.particles.clear();
}

// Step 2 on rows [row_begin, row_end): their nodes to split, flagged and appended to `out`.
void list_nodes(State& s, int row_begin, int row_end, std::vector<std::uint32_t>& out) {
  Grid& g = s.grid;
  SplitNodes& sp = g.split;
  const double full = s.setup.merge_mass * (1.0 + kMergeMargin);
  const Node* const nodes = g.arrays.nodes.data();
  const std::uint8_t* const windows = g.arrays.windows.data();
  const std::size_t end = static_cast<std::size_t>(row_end) * g.nx;
  for (std::size_t k = static_cast<std::size_t>(row_begin) * g.nx; k < end; ++k) {
    const double m = nodes[k].m;
    if (!(m > 0.0 && m < full)) continue;
    // The node's windows: those of the stencils that hold it (rows below row_lo hold none).
    unsigned outside = 0;
    each_first_node(g, k, g.row_lo, [&](std::size_t f) { outside |= windows[f]; });
    if (!pore_contact::may_oppose(outside)) continue;
    sp.node[k] = 1;
    out.push_back(static_cast<std::uint32_t>(k));
  }
}

// Step 3 on particles [begin, end): those whose first node reaches a listed node, appended to
// `out`.
void list_particles(const SplitNodes& sp, std::size_t begin, std::size_t end,
                    std::vector<std::uint32_t>& out) {
  const std::uint8_t* const reach = sp.reach.data();
  const std::uint32_t* const first = sp.first_node.data();
  for (std::size_t p = begin; p < end; ++p) {
    if (reach[first[p]] != 0) out.push_back(static_cast<std::uint32_t>(p));
  }
}

// The band of a particle whose first node is `first`: kBandRows rows of first nodes. A stencil
// holds the three rows from its first, so a band's particles reach its own rows and the next
// band's, and bands two apart share no node: the bands of one parity can scatter at once.
constexpr int kBandRows = 3;
int band_of(const Grid& g, std::uint32_t first) {
  return static_cast<int>(first / g.nx) / kBandRows;
}

// The threads' listed particles, in particle order within each band, into sp.particles, band
// after band (sp.band_begin[c]: band c's first; a counting sort).
void sort_by_band(Grid& g) {
  SplitNodes& sp = g.split;
  std::fill(sp.band_begin.begin(), sp.band_begin.end(), 0);
  for (const std::vector<std::uint32_t>& list : sp.thread_particles) {
    for (const std::uint32_t p : list) ++sp.band_begin[band_of(g, sp.first_node[p]) + 1];
  }
  for (std::size_t c = 1; c < sp.band_begin.size(); ++c) sp.band_begin[c] += sp.band_begin[c - 1];
  sp.particles.resize(sp.band_begin.back());
  sp.band_fill.assign(sp.band_begin.begin(), sp.band_begin.end() - 1);
  for (const std::vector<std::uint32_t>& list : sp.thread_particles) {
    for (const std::uint32_t p : list) {
      sp.particles[sp.band_fill[band_of(g, sp.first_node[p])]++] = p;
    }
  }
}

// Calls f(begin, end) for the ranges of sp.particles of the bands of `parity` that thread t of
// `threads` takes: consecutive bands, about as many particles for each thread.
template <class F>
void each_band(const SplitNodes& sp, int parity, int t, int threads, F&& f) {
  const std::size_t bands = sp.band_begin.size() - 1;
  std::size_t total = 0;
  for (std::size_t c = parity; c < bands; c += 2) total += sp.band_begin[c + 1] - sp.band_begin[c];
  if (total == 0) return;
  std::size_t before = 0;
  for (std::size_t c = parity; c < bands; c += 2) {
    const std::size_t count = sp.band_begin[c + 1] - sp.band_begin[c];
    const std::size_t owner = std::min<std::size_t>(before * threads / total, threads - 1);
    before += count;
    if (static_cast<int>(owner) == t && count > 0) f(sp.band_begin[c], sp.band_begin[c + 1]);
  }
}

// Step 4 for listed particles [begin, end): their w_ip n_p added to the listed nodes' normals.
void sum_normals(State& s, std::size_t begin, std::size_t end) {
  Grid& g = s.grid;
  SplitNodes& sp = g.split;
  const Particles& P = s.particles;
  for (std::size_t j = begin; j < end; ++j) {
    const std::uint32_t p = sp.particles[j];
    const auto kx = kernel::quadratic(P.x[p] * g.inv_dx + g.gx);
    const auto ky = kernel::quadratic(P.y[p] * g.inv_dx + g.gy);
    for (int b = 0; b < 3; ++b) {
      const std::size_t r = static_cast<std::size_t>(ky.base + b) * g.nx;
      for (int a = 0; a < 3; ++a) {
        const std::size_t k = r + g.col[kx.base + 1 + a];
        if (sp.node[k] == 0) continue;
        const double w = kx.w[a] * ky.w[b];
        sp.normal[k].x += w * P.nx[p];
        sp.normal[k].y += w * P.ny[p];
      }
    }
  }
}

// Step 5: the listed particles scattered into the listed nodes' two fields, a block of them at
// a time: copied side by side so that prepare_block (the one field's arithmetic) runs on them,
// then each pair added to the field its normal picks.
struct ScatterSplit {
  static constexpr std::size_t n = kScatterBlock;
  struct Copy {
    alignas(64) double x[n], y[n], vx[n], vy[n], cxx[n], cxy[n], cyx[n], cyy[n];
    alignas(64) double txx[n], txy[n], tyy[n];
  };
  template <bool kAvx2>
  [[gnu::always_inline]] static void run(State& s, double dt, std::size_t begin,
                                         std::size_t end) {
    Grid& g = s.grid;
    Particles& P = s.particles;
    const SplitNodes& sp = g.split;
    Node* const nodes = g.arrays.nodes.data();
    const std::ptrdiff_t field2 = static_cast<std::ptrdiff_t>(g.field2), nx = g.nx;
    const std::uint32_t* const list = sp.particles.data() + begin;
    const std::size_t count = end - begin;
    Copy c;
    ScatterBlock sb;
    for (std::size_t b0 = 0; b0 < count; b0 += n) {
      const std::size_t nb = std::min(n, count - b0);
      for (std::size_t i = 0; i < nb; ++i) {
        const std::uint32_t p = list[b0 + i];
        c.x[i] = P.x[p], c.y[i] = P.y[p], c.vx[i] = P.vx[p], c.vy[i] = P.vy[p];
        c.cxx[i] = P.C.xx[p], c.cxy[i] = P.C.xy[p], c.cyx[i] = P.C.yx[p], c.cyy[i] = P.C.yy[p];
        c.txx[i] = P.tau.xx[p], c.txy[i] = P.tau.xy[p], c.tyy[i] = P.tau.yy[p];
      }
      prepare_block<true, false>(nb, dt, s.setup, g, P.mass, c.x, c.y, c.vx, c.vy, c.cxx, c.cxy,
                                 c.cyx, c.cyy, c.txx, c.txy, c.tyy, &sb);
      for (std::size_t k = 0; k < nb; ++k) {
        const std::uint32_t p = list[b0 + k];
        const double pnx = P.nx[p], pny = P.ny[p];
        std::uint16_t bits = 0;
        for (int b = 0; b < 3; ++b) {
          const std::ptrdiff_t row = sb.row0[k] + b * nx;
          const double lo[4] = {sb.wm[b][k], sb.qx[b][k], sb.qy[b][k], 0.0};
          const double hi[4] = {0.0, sb.qxx[b][k], sb.qyx[b][k], 0.0};
          for (int a = 0; a < 3; ++a) {
            const std::ptrdiff_t i = row + sb.cols[a][k];
            if (sp.node[i] == 0) continue;
            const NodeNormal m = sp.normal[i];
            const bool second = pore_contact::second_field(pnx, pny, m.x, m.y);
            add_to_node<kAvx2>(nodes[i + (second ? field2 : 0)], sb.wx[a][k], sb.wdx[a][k], lo,
                               hi);
            bits |= static_cast<std::uint16_t>(second << (3 * b + a));
          }
        }
        P.field_bits[p] = bits;
      }
    }
  }
};

}  // namespace

void split_fields(State& s, double dt, ThreadPool& pool) {
  Grid& g = s.grid;
  SplitNodes& sp = g.split;
  const int threads = pool.size();
  // Sized on the first step (the same sizes after it).
  sp.thread_nodes.resize(threads), sp.thread_particles.resize(threads);
  sp.band_begin.resize(static_cast<std::size_t>(g.ny / kBandRows + 2));
  clear_last(s);
  const std::size_t rows = static_cast<std::size_t>(g.row_hi - g.row_lo);
  pool.run([&](int t) {
    sp.thread_nodes[t].clear();
    list_nodes(s, g.row_lo + static_cast<int>(pool.begin(rows, t)),
               g.row_lo + static_cast<int>(pool.end(rows, t)), sp.thread_nodes[t]);
  });
  for (const std::vector<std::uint32_t>& list : sp.thread_nodes) {
    sp.nodes.insert(sp.nodes.end(), list.begin(), list.end());
  }
  if (sp.nodes.empty()) return;
  for (const std::uint32_t k : sp.nodes) {
    each_first_node(g, k, 0, [&](std::size_t f) { sp.reach[f] = 1; });
  }
  const std::size_t n = s.particles.n;
  pool.run([&](int t) {
    sp.thread_particles[t].clear();
    list_particles(sp, pool.begin(n, t), pool.end(n, t), sp.thread_particles[t]);
  });
  sort_by_band(g);
  Node* const nodes = g.arrays.nodes.data();
  for (const std::uint32_t k : sp.nodes) {
    sp.normal[k] = NodeNormal{0, 0}, nodes[k] = Node{0, 0, 0, 0};
  }
  // Steps 4 and 5, the even bands and then the odd ones (with one thread as with several, so
  // that a node gets its particles in the same order).
  for (int parity = 0; parity < 2; ++parity) {
    pool.run([&](int t) {
      each_band(sp, parity, t, threads,
                [&](std::size_t b, std::size_t e) { sum_normals(s, b, e); });
    });
  }
  for (int parity = 0; parity < 2; ++parity) {
    pool.run([&](int t) {
      each_band(sp, parity, t, threads,
                [&](std::size_t b, std::size_t e) { run_variant<ScatterSplit>(s, dt, b, e); });
    });
  }
}

}  // namespace compaction
