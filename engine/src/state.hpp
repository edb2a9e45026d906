// The simulation state: particles (structure of arrays), the background grid and the constants
// of the scene. Plain data; the stages of a time step (p2g.cpp, grid_update.cpp, g2p.cpp, ...)
// operate on it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "compaction/params.hpp"
#include "matrix.hpp"
#include "plasticity.hpp"
#include "scatter_rows.hpp"

namespace compaction {

// Every particle carries the same mass and initial volume (a regular lattice of a uniform
// solid), so those are scalars of the set, not arrays.
struct Particles {
  std::size_t n = 0;
  double mass = 0.0;  // [kg/m] (per unit depth)
  double vol0 = 0.0;  // initial area                                        [m^2]
  std::vector<double> x, y;     // position                                  [m]
  std::vector<double> vx, vy;   // velocity                                  [m/s]
  Mat2Columns C;                // APIC affine velocity = velocity gradient  [1/s]
  Mat2Columns Fe;               // elastic deformation gradient (double: strain steps ~1e-7)
  Sym2Columns tau;              // Kirchhoff stress                          [N/m]
  std::vector<double> dep;      // plastic strain accumulated in the current frame
  std::vector<double> ep;       // plastic strain accumulated up to the last frame
  std::vector<double> x0;       // initial position x, for strut deflections [m]
  std::vector<std::int32_t> strut;  // vertical strut id, -1 when not in a strut
  std::vector<std::uint8_t> strut_mid;  // 1: middle half of the strut, 0: its ends
  // split_fields only (else empty): the unit normal of the nearest pore face, pointing from
  // the pore into the solid, carried with the material (pore_contact.hpp)
  std::vector<double> nx, ny;
  // split_fields only: bit 3 b + a set when p2g put the particle's pair with stencil node
  // (a, b) into the node's second field, so that g2p reads the same field without the test
  std::vector<std::uint16_t> field_bits;
};

// Grid node: mass and momentum (after the grid update: velocity in vx, vy).
struct Node {
  double m, vx, vy, pad_;
};

// A node's normal (split_fields): its two components side by side, one cache line for four
// nodes, as P2G reads and writes them together.
struct NodeNormal {
  double x, y;
};

// Node arrays that P2G scatters into: one set for the grid, one more per extra thread.
struct NodeArrays {
  std::vector<Node> nodes;          // nodes[j * nx + i]
  std::vector<double> mx, my;       // pic_flip only: momentum before forces (for v_old)
  // split_fields only: the windows that the normals of the particles whose stencil starts at
  // this node lie outside of, or'ed (pore_contact::outside_windows)
  std::vector<std::uint8_t> windows;
};

// split_fields: the nodes of this step whose two fields may differ from one (not full, normals
// that may oppose; pore_contact.hpp), and the particles that reach them (p2g_split_fields.cpp).
// Sized once (the bands and the threads' lists on the first step); only the listed nodes are
// set in `node`, hold a normal and a second field.
struct SplitNodes {
  std::vector<std::uint8_t> node;         // node[k]: node k is listed
  std::vector<std::uint8_t> reach;        // reach[k]: the stencil from node k holds a listed one
  std::vector<std::uint32_t> nodes;       // the listed nodes
  std::vector<std::uint32_t> particles;   // the particles that reach a listed node, by band
  std::vector<std::uint32_t> band_begin;  // band c's particles from particles[band_begin[c]]
  std::vector<std::uint32_t> band_fill;   // the counting sort's work array
  std::vector<std::vector<std::uint32_t>> thread_nodes;      // each thread's listed nodes
  std::vector<std::vector<std::uint32_t>> thread_particles;  // and particles
  std::vector<std::uint32_t> first_node;  // each particle's first stencil node (p2g)
  std::vector<NodeNormal> normal;         // the node normal, sum of w n_p, on the listed nodes
};

struct Grid {
  int nx = 0, ny = 0;   // nodes
  int gx = 0, gy = 0;   // ghost offset: node (i, j) sits at ((i - gx) dx, (j - gy) dx)
  double dx = 0.0, inv_dx = 0.0;
  bool periodic_x = false;
  std::vector<int> col;     // col[base + 1 + k]: node column of stencil column base + k
  NodeArrays arrays;                  // after the grid update: velocities, in place
  std::vector<NodeArrays> scratch;    // P2G targets of threads 1..T-1
  SplitNodes split;                   // split_fields only
  ScatterRows scatter_rows;           // the rows each P2G thread writes alone (T > 1)
  int row_lo = 0, row_hi = 0;  // rows that can carry mass this step, [row_lo, row_hi)
  int cells_x = 0, cells_y = 0;  // grid cells across and along the specimen (map rows: cells_y)
  // split_fields only: nodes holds two fields, the second (particles whose normal opposes the
  // node's) from this offset on, so that the transfers pick a field by index. 0 with one field.
  std::size_t field2 = 0;
};

// Constants of the scene that the stages need.
struct Setup {
  Material material;
  double V = 0.0;       // plate speed                                   [m/s]
  double h0 = 0.0;      // initial height                                [m]
  double width = 0.0;   // specimen width                                [m]
  double c_p = 0.0;     // P-wave speed                                  [m/s]
  double scale = 0.0;   // MLS force factor: vol0 * D^-1 = 4 vol0 / dx^2
  double vol0 = 0.0;    // initial particle area (force factor of the B-spline gradient) [m^2]
  Transfer transfer = Transfer::apic;
  Gradient gradient = Gradient::mls;
  double flip_ratio = 0.0;
  PlateContact contact = PlateContact::bonded;
  bool split_fields = false;  // pore_contact = split_fields
  double merge_mass = 0.0;    // a node of two fields merges them from this mass on [kg/m]
  bool side_walls = false;
  int n_struts = 0;
  double strut_thickness = 0.0;  // [m]
};

// What one step measured, reduced over particles, for stability and dt.
struct StepMeasure {
  double max_v2 = 0.0;      // largest squared particle speed (NaN if any is NaN)
  double y_min = 0.0, y_max = 0.0, x_min = 0.0, x_max = 0.0;
  bool bad_jacobian = false; // some particle had J <= 0 or a non-finite state
};

// The measures of two sets of particles as one: maxima, minima (NaN speeds win) and an or, so the
// result does not depend on the order the sets are combined in.
inline StepMeasure combine(const StepMeasure& a, const StepMeasure& b) {
  StepMeasure m;
  m.max_v2 = std::isnan(a.max_v2) || std::isnan(b.max_v2) ? std::nan("")
                                                           : std::max(a.max_v2, b.max_v2);
  m.y_min = std::min(a.y_min, b.y_min), m.y_max = std::max(a.y_max, b.y_max);
  m.x_min = std::min(a.x_min, b.x_min), m.x_max = std::max(a.x_max, b.x_max);
  m.bad_jacobian = a.bad_jacobian || b.bad_jacobian;
  return m;
}

// The plates' y-impulses on the material over some rows of one step.
struct PlateImpulses {
  double top = 0.0, bottom = 0.0;
};

// Time, plate position and impulses.
struct Clock {
  double t = 0.0;
  std::int64_t step = 0;
  double top_impulse = 0.0;     // y-impulse of the top plate on the material, this frame
  double bottom_impulse = 0.0;  // y-impulse of the bottom plate on the material, this frame
  double plate_work = 0.0;      // work of the plates on the material since t = 0
  double top_y(const Setup& s) const { return s.h0 - s.V * t; }
};

struct State {
  Setup setup;
  Particles particles;
  Grid grid;
  Clock clock;
  StepMeasure measure;
  std::vector<StepMeasure> partial_measures;  // one per thread, reduced into measure
  std::vector<PlateImpulses> partial_impulses;  // one per thread, summed in thread order
};

}  // namespace compaction
