// Grid to particle transfer, then the particle's own update (Hu et al. 2018, Eqs. 17-19, 30):
//   v_p = sum w v_i                     (apic; pic_flip blends in the FLIP increment)
//   C_p = D^-1 sum w v_i (x_i - x_p)^T  (= the velocity gradient for quadratic B-splines)
//   x_p += dt v_p,  Fe <- (I + dt C_p) Fe,  then the return mapping (plasticity.hpp), run on
//   blocks of kBlock particles at a time so that it vectorises across them.
// gradient = bspline updates Fe with the exact gradient sum v_i (x) grad w_ip instead of C_p.
// pore_contact = split_fields reads each node's velocity from the field p2g put the particle
// in (its field bits), and carries the particle's face normal with the flow (pore_contact.hpp).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>

#include "kernel.hpp"
#include "pore_contact.hpp"
#include "simd_dispatch.hpp"
#include "stages.hpp"

namespace compaction {

namespace {

// The particles' side of one block, structure of arrays: the transfer writes it, the return
// mapping and the bookkeeping read it.
struct GatherBlock {
  alignas(64) double x[kBlock], y[kBlock], v2[kBlock];
};

// The step's measures over a thread's particles as eight running lanes, which one vector
// updates at once: maxima and minima are exact, so the lanes' order does not change them. A
// NaN speed is counted apart and makes max_v2 NaN; a NaN position is ignored, as std::min and
// std::max ignore their second argument's NaN.
struct MeasureLanes {
  static constexpr std::size_t kLanes = 8;
  alignas(64) double max_v2[kLanes], nan_v2[kLanes];
  alignas(64) double x_min[kLanes], x_max[kLanes], y_min[kLanes], y_max[kLanes];
};

// What the transfer of one block reads besides the particles.
struct GridView {
  double dx, inv_dx, c_scale, gxo, gyo;
  std::ptrdiff_t nx;
  double wrap, width;  // periodic wrap: wrap = width; otherwise 0 and infinity
  double alpha;        // FLIP share (pic_flip)
};

// split_fields: the offset of the second field in the nodes, the particles' field bits (as p2g
// set them) and their normals (else 0 and null).
struct SplitView {
  std::ptrdiff_t second;
  const std::uint16_t* bits;
  double *pnx, *pny;
};

// The velocities of a block's stencil nodes, {vx, vy} of node (a, b) of particle i at
// v[3 b + a][i].
struct NodePairs {
  alignas(64) double v[9][kBlock][2];
};

// Copies each particle's nine node velocities into the block, one pair at a time (a 16-byte
// load and store; vx and vy are neighbours in a Node), so that the transfer reads them as
// vectors. Read inside the vectorised transfer, every vx and vy is assembled from single loads
// (18 a particle), and G2P takes about 2 ns per particle-step longer (docs/engine.md).
// kSplit: the node of the particle's field (its field bits, as p2g set them).
template <bool kSplit>
[[gnu::always_inline]] inline void gather_node_pairs(
    std::size_t n, const GridView& v, const int* __restrict col, const Node* __restrict nodes,
    const double* __restrict px, const double* __restrict py, std::ptrdiff_t second,
    const std::uint16_t* __restrict field_bits, NodePairs* __restrict out) {
  for (std::size_t i = 0; i < n; ++i) {
    const int bx = kernel::quadratic(px[i] * v.inv_dx + v.gxo).base;
    const int by = kernel::quadratic(py[i] * v.inv_dx + v.gyo).base;
    const std::ptrdiff_t c[3] = {col[bx + 1], col[bx + 2], col[bx + 3]};
    [[maybe_unused]] std::ptrdiff_t bits = 0;
    if constexpr (kSplit) bits = field_bits[i];
#pragma GCC unroll 3
    for (int b = 0; b < 3; ++b) {
      const std::ptrdiff_t row = (by + b) * v.nx;
#pragma GCC unroll 3
      for (int a = 0; a < 3; ++a) {
        std::ptrdiff_t k = row + c[a];
        if constexpr (kSplit) k += -((bits >> (3 * b + a)) & 1) & second;
        std::memcpy(out->v[3 * b + a][i], &nodes[k].vx, 2 * sizeof(double));
      }
    }
  }
}

// Whether any of n particles' field bits is set, as a loop that vectorises.
[[gnu::always_inline]] inline bool any_bits(const std::uint16_t* __restrict bits, std::size_t n) {
  unsigned any = 0;
  for (std::size_t i = 0; i < n; ++i) any |= bits[i];
  return any != 0;
}

// Grid to particle transfer for the n particles of one block, up to the trial Fe, from the
// node velocities gather_node_pairs copied. Every array is __restrict, so that the compiler
// vectorises it across the block: arithmetic without branches. (Without that promise the
// stores to the normals of split_fields might alias the node pairs, and the loop would not
// vectorise.) pic_flip's momenta before forces are loaded node by node.
template <bool kApic, bool kExact, bool kSplit>
[[gnu::always_inline]] inline void transfer_block(
    std::size_t n, double dt, const GridView& v, const int* __restrict col,
    const NodePairs* __restrict np, const double* __restrict mx, const double* __restrict my,
    double* __restrict px, double* __restrict py, double* __restrict pvx,
    double* __restrict pvy, double* __restrict cxx, double* __restrict cxy,
    double* __restrict cyx, double* __restrict cyy, const double* __restrict fxx,
    const double* __restrict fxy, const double* __restrict fyx, const double* __restrict fyy,
    GatherBlock* __restrict gb, ReturnMapBlock* __restrict blk, double* __restrict pnx,
    double* __restrict pny) {
  const double dx = v.dx, inv_dx = v.inv_dx, c_scale = v.c_scale, alpha = v.alpha;
  struct Pair {
    double vx, vy;
  };
  for (std::size_t i = 0; i < n; ++i) {
    // Node (a, b) as this particle sees it: its field's (split_fields) or the one field.
    auto node = [&](int a, int b) {
      return Pair{np->v[3 * b + a][i][0], np->v[3 * b + a][i][1]};
    };
    const auto kx = kernel::quadratic(px[i] * inv_dx + v.gxo);
    const auto ky = kernel::quadratic(py[i] * inv_dx + v.gyo);
    // B = sum_ab wx_a wy_b v_ab (dx_a, dy_b)^T, summed row by row with the x-weights
    // (and x-weighted offsets) applied first.
    const double wdx0 = kx.w[0] * (0 - kx.fx) * dx, wdx1 = kx.w[1] * (1 - kx.fx) * dx,
                 wdx2 = kx.w[2] * (2 - kx.fx) * dx;
    // pic_flip's momenta: the node columns (periodic wrap)
    const std::ptrdiff_t c0 = col[kx.base + 1], c1 = col[kx.base + 2], c2 = col[kx.base + 3];
    double vx = 0, vy = 0, bxx = 0, bxy = 0, byx = 0, byy = 0, ox = 0, oy = 0;
    double gxx = 0, gxy = 0, gyx = 0, gyy = 0;  // exact velocity gradient (times dx)
#pragma GCC unroll 3
    for (int b = 0; b < 3; ++b) {
      const double wy = ky.w[b], wdy = ky.w[b] * (b - ky.fx) * dx;
      const std::ptrdiff_t row = (ky.base + b) * v.nx;
      const Pair n0 = node(0, b), n1 = node(1, b), n2 = node(2, b);
      const double sx = kx.w[0] * n0.vx + kx.w[1] * n1.vx + kx.w[2] * n2.vx;
      const double sy = kx.w[0] * n0.vy + kx.w[1] * n1.vy + kx.w[2] * n2.vy;
      const double sdx = wdx0 * n0.vx + wdx1 * n1.vx + wdx2 * n2.vx;
      const double sdy = wdx0 * n0.vy + wdx1 * n1.vy + wdx2 * n2.vy;
      vx += wy * sx, vy += wy * sy;
      bxx += wy * sdx, bxy += wdy * sx;
      byx += wy * sdy, byy += wdy * sy;
      if constexpr (kExact) {  // grad w = (dw_a w_b, w_a dw_b) / dx
        const double tx = kx.dw[0] * n0.vx + kx.dw[1] * n1.vx + kx.dw[2] * n2.vx;
        const double ty = kx.dw[0] * n0.vy + kx.dw[1] * n1.vy + kx.dw[2] * n2.vy;
        gxx += wy * tx, gxy += ky.dw[b] * sx;
        gyx += wy * ty, gyy += ky.dw[b] * sy;
      }
      if constexpr (!kApic) {
        ox += kx.w[0] * wy * mx[row + c0], oy += kx.w[0] * wy * my[row + c0];
        ox += kx.w[1] * wy * mx[row + c1], oy += kx.w[1] * wy * my[row + c1];
        ox += kx.w[2] * wy * mx[row + c2], oy += kx.w[2] * wy * my[row + c2];
      }
    }
    const Mat2 c{bxx * c_scale, bxy * c_scale, byx * c_scale, byy * c_scale};
    cxx[i] = c.xx, cxy[i] = c.xy, cyx[i] = c.yx, cyy[i] = c.yy;
    if constexpr (kSplit) {  // a material normal follows F^-T: dn/dt = -C^T n
      const double nx = pnx[i], ny = pny[i];
      double ux = nx - dt * (c.xx * nx + c.yx * ny), uy = ny - dt * (c.xy * nx + c.yy * ny);
      const double len = std::sqrt(ux * ux + uy * uy);
      if (len > 0.0) ux /= len, uy /= len;
      pnx[i] = ux, pny[i] = uy;
    }
    double vx_new = vx, vy_new = vy;
    if constexpr (!kApic) {
      vx_new = alpha * (pvx[i] + vx - ox) + (1.0 - alpha) * vx;
      vy_new = alpha * (pvy[i] + vy - oy) + (1.0 - alpha) * vy;
    }
    pvx[i] = vx_new, pvy[i] = vy_new;
    gb->v2[i] = vx_new * vx_new + vy_new * vy_new;
    double x = px[i] + dt * vx;
    const double y = py[i] + dt * vy;
    // periodic wrap into [0, width) as arithmetic (the same bits as branches would give)
    x -= x >= v.width ? v.wrap : 0.0;
    x += x < 0.0 ? v.wrap : 0.0;
    px[i] = x, py[i] = y;
    gb->x[i] = x, gb->y[i] = y;

    const Mat2 grad = kExact ? Mat2{gxx * inv_dx, gxy * inv_dx, gyx * inv_dx, gyy * inv_dx} : c;
    const Mat2 f{fxx[i], fxy[i], fyx[i], fyy[i]};  // trial Fe = (I + dt grad v) Fe
    blk->fxx[i] = f.xx + dt * (grad.xx * f.xx + grad.xy * f.yx);
    blk->fxy[i] = f.xy + dt * (grad.xx * f.xy + grad.xy * f.yy);
    blk->fyx[i] = f.yx + dt * (grad.yx * f.xx + grad.yy * f.yx);
    blk->fyy[i] = f.yy + dt * (grad.yx * f.xy + grad.yy * f.yy);
  }
}

// dep += plastic for a block's particles: the plastic strain of this frame (ep, the running
// total, is updated once per frame).
[[gnu::always_inline]] inline void add_plastic(double* __restrict dep,
                                               const double* __restrict plastic, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) dep[i] += plastic[i];
}

// The measures of no particle, which combine() with any others gives those others.
StepMeasure no_particles() {
  StepMeasure m;
  m.y_min = m.x_min = std::numeric_limits<double>::infinity();
  m.y_max = m.x_max = -std::numeric_limits<double>::infinity();
  return m;
}

MeasureLanes no_lanes() {
  MeasureLanes l;
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < MeasureLanes::kLanes; ++j) {
    l.max_v2[j] = 0.0, l.nan_v2[j] = 0.0;
    l.x_min[j] = l.y_min[j] = inf, l.x_max[j] = l.y_max[j] = -inf;
  }
  return l;
}

// Adds the first `groups` eight particles of a block to the lanes, as a loop that vectorises.
[[gnu::always_inline]] inline void add_to_lanes(const GatherBlock* __restrict gb,
                                                std::size_t groups, MeasureLanes* __restrict l) {
  constexpr std::size_t w = MeasureLanes::kLanes;
  for (std::size_t g = 0; g < groups; ++g) {
    for (std::size_t j = 0; j < w; ++j) {
      const double v2 = gb->v2[g * w + j], x = gb->x[g * w + j], y = gb->y[g * w + j];
      l->nan_v2[j] += v2 != v2 ? 1.0 : 0.0;
      l->max_v2[j] = std::max(l->max_v2[j], v2);
      l->x_min[j] = std::min(l->x_min[j], x), l->x_max[j] = std::max(l->x_max[j], x);
      l->y_min[j] = std::min(l->y_min[j], y), l->y_max[j] = std::max(l->y_max[j], y);
    }
  }
}

// The measures the lanes hold.
StepMeasure from_lanes(const MeasureLanes& l) {
  StepMeasure m = no_particles();
  double nan = 0.0;
  for (std::size_t j = 0; j < MeasureLanes::kLanes; ++j) {
    nan += l.nan_v2[j];
    m.max_v2 = std::max(m.max_v2, l.max_v2[j]);
    m.x_min = std::min(m.x_min, l.x_min[j]), m.x_max = std::max(m.x_max, l.x_max[j]);
    m.y_min = std::min(m.y_min, l.y_min[j]), m.y_max = std::max(m.y_max, l.y_max[j]);
  }
  if (nan != 0.0) m.max_v2 = std::nan("");
  return m;
}

// The gather into particles [begin, end), one block at a time (run_loop in simd_dispatch.hpp
// makes its variants and copies; both copies run the same code).
template <bool kApic, bool kExact, bool kSplit = false>
struct Gather {
  template <bool kAvx2>
  [[gnu::always_inline]] static StepMeasure run(Particles& P, const Setup& s, const Grid& g,
                                                std::size_t begin, std::size_t end, double dt) {
    const GridView view{g.dx,
                        g.inv_dx,
                        kernel::kInverseInertia * g.inv_dx * g.inv_dx,
                        static_cast<double>(g.gx),
                        static_cast<double>(g.gy),
                        g.nx,
                        g.periodic_x ? s.width : 0.0,
                        g.periodic_x ? s.width : std::numeric_limits<double>::infinity(),
                        s.flip_ratio};
    bool bad_jacobian = false;
    ReturnMapBlock blk;  // the block's trial Fe, and the plastic increments
    GatherBlock gb;      // positions and squared speeds, for the step's measures
    NodePairs pairs;     // the block's node velocities
    MeasureLanes lanes = no_lanes();
    for (std::size_t b0 = begin; b0 < end; b0 += kBlock) {
      const std::size_t nb = std::min(kBlock, end - b0);
      SplitView split{};
      if constexpr (kSplit) {
        split = {static_cast<std::ptrdiff_t>(g.field2), P.field_bits.data() + b0,
                 P.nx.data() + b0, P.ny.data() + b0};
      }
      // split_fields: most blocks have no pair in a second field (p2g_split_fields.cpp).
      if (kSplit && any_bits(split.bits, nb)) {
        gather_node_pairs<true>(nb, view, g.col.data(), g.arrays.nodes.data(), P.x.data() + b0,
                                P.y.data() + b0, split.second, split.bits, &pairs);
      } else {
        gather_node_pairs<false>(nb, view, g.col.data(), g.arrays.nodes.data(), P.x.data() + b0,
                                 P.y.data() + b0, 0, nullptr, &pairs);
      }
      transfer_block<kApic, kExact, kSplit>(
          nb, dt, view, g.col.data(), &pairs, g.arrays.mx.data(),
          g.arrays.my.data(), P.x.data() + b0, P.y.data() + b0, P.vx.data() + b0,
          P.vy.data() + b0, P.C.xx.data() + b0, P.C.xy.data() + b0, P.C.yx.data() + b0,
          P.C.yy.data() + b0, P.Fe.xx.data() + b0, P.Fe.xy.data() + b0, P.Fe.yx.data() + b0,
          P.Fe.yy.data() + b0, &gb, &blk, split.pnx, split.pny);
      // Fe and tau straight into the particles; the block keeps the trial Fe.
      double* const fe[4] = {P.Fe.xx.data() + b0, P.Fe.xy.data() + b0, P.Fe.yx.data() + b0,
                             P.Fe.yy.data() + b0};
      double* const tau[3] = {P.tau.xx.data() + b0, P.tau.xy.data() + b0, P.tau.yy.data() + b0};
      return_map_block<false>(blk, nb, s.material, fe[0], fe[1], fe[2], fe[3], tau[0], tau[1],
                              tau[2]);
      const bool handed_back = any_redo(blk, nb);
      if (handed_back) {
        return_map_block<true>(blk, nb, s.material, fe[0], fe[1], fe[2], fe[3], tau[0], tau[1],
                               tau[2]);
      }
      add_plastic(P.dep.data() + b0, blk.plastic, nb);  // 0 for a particle handed back
      if (handed_back && any_redo(blk, nb)) {
        for (std::size_t i = 0; i < nb; ++i) {
          if (blk.redo[i] == 0.0) continue;
          const std::size_t p = b0 + i;  // outside the series' range: the exact update
          Mat2 f{blk.fxx[i], blk.fxy[i], blk.fyx[i], blk.fyy[i]};
          Sym2 t = P.tau[p];  // return_map leaves it when J <= 0, which ends the run
          const double plastic = return_map(f, s.material, t);
          if (std::isnan(plastic)) bad_jacobian = true;
          P.Fe.set(p, f), P.tau.set(p, t);
          P.dep[p] += plastic;
        }
      }
      // The block's last group of eight is filled up with particles that change no measure.
      const std::size_t groups = (nb + MeasureLanes::kLanes - 1) / MeasureLanes::kLanes;
      for (std::size_t i = nb; i < groups * MeasureLanes::kLanes; ++i) {
        gb.v2[i] = 0.0, gb.x[i] = gb.y[i] = std::nan("");
      }
      add_to_lanes(&gb, groups, &lanes);
    }
    StepMeasure m = from_lanes(lanes);
    m.bad_jacobian = bad_jacobian;
    return m;
  }
};

}  // namespace

// Threads take chunks of kChunk particles in turn: the return mapping costs more where the
// material yields (a band holds a few rows), so equal shares would leave one thread waiting.
// Every particle's update is its own, and the measures are maxima, minima and an or, so the
// result does not depend on which thread took which chunk. kChunk is a whole number of
// blocks, so the blocks are those of one thread.
constexpr std::size_t kChunk = 32 * kBlock;

void g2p(State& s, double dt, ThreadPool& pool) {
  std::vector<StepMeasure>& parts = s.partial_measures;  // sized once, one per thread
  const std::size_t n = s.particles.n;
  std::atomic<std::size_t> next{0};
  pool.run([&](int t) {
    StepMeasure m = no_particles();
    for (std::size_t b; (b = next.fetch_add(kChunk, std::memory_order_relaxed)) < n;) {
      const std::size_t e = std::min(b + kChunk, n);
      const StepMeasure chunk =
          s.setup.split_fields  // apic and mls (validate())
              ? run_variant<Gather<true, false, true>>(s.particles, s.setup, s.grid, b, e, dt)
              : run_loop<Gather>(s.setup.transfer, s.setup.gradient, s.particles, s.setup,
                                 s.grid, b, e, dt);
      m = combine(m, chunk);
    }
    parts[t] = m;
  });
  StepMeasure m = parts[0];
  for (std::size_t t = 1; t < parts.size(); ++t) m = combine(m, parts[t]);
  s.measure = m;
}

}  // namespace compaction
