// The state of a 3D pseudo-1D column (geometry pseudo1d_3d): particles (structure of arrays),
// the background grid, the constants of the scene. Plain data, as state.hpp for 2D; the stages
// of a 3D time step (p2g_3d.cpp, grid_update_3d.cpp, g2p_3d.cpp) operate on it.
//
// The column is one unit cell across in x and z, periodic in both by index wrapping, and
// n_rows unit cells tall along y, the compression axis (as in 2D). Units are 3D: masses in kg,
// stresses in N/m^2, the plates' impulses in N s (their stress is impulse / (width^2 time)).
#pragma once

#include <cstddef>
#include <vector>

#include "compaction/params.hpp"
#include "plasticity_3d.hpp"
#include "scatter_rows.hpp"
#include "state.hpp"  // Clock, StepMeasure, PlateImpulses (dimension-free)

namespace compaction {

// Every particle carries the same mass and initial volume (a regular lattice of a uniform
// solid), so those are scalars of the set.
struct Particles3D {
  std::size_t n = 0;
  double mass = 0.0;  // [kg]
  double vol0 = 0.0;  // initial volume                                      [m^3]
  std::vector<double> x, y, z;     // position (x, z wrapped into [0, width)) [m]
  std::vector<double> vx, vy, vz;  // velocity                               [m/s]
  std::vector<Mat3> C;             // APIC affine velocity = velocity gradient [1/s]
  std::vector<Mat3> Fe;            // elastic deformation gradient           [-]
  std::vector<Mat3> tau;           // Kirchhoff stress (symmetric)           [N/m^2]
  std::vector<double> dep;         // plastic strain accumulated in the current frame [-]
};

// Grid node: mass and momentum (after the grid update: velocity in vx, vy, vz).
struct Node3D {
  double m, vx, vy, vz;
};

struct Grid3D {
  int nx = 0, ny = 0, nz = 0;  // nodes; nx = nz = cells across (periodic, no ghosts)
  int gy = 0;                  // ghost offset: node (i, j, k) sits at (i dx, (j - gy) dx, k dx)
  double dx = 0.0, inv_dx = 0.0;
  // wrap[base + 1 + a]: the node column of stencil column base + a, base in [-1, nx - 1], for x
  // and z alike (nx = nz): wrapped once here so that the transfers never compute a modulo.
  std::vector<int> wrap;
  std::vector<Node3D> nodes;   // nodes[(j * nz + k) * nx + i]: a y-layer is contiguous
  int row_lo = 0, row_hi = 0;  // y-layers that can carry mass this step, [row_lo, row_hi)
  int cells_across = 0, cells_y = 0;  // grid cells across (x and z) and along the column
  // With threads (p2g_3d.cpp): the P2G targets of threads 1..T-1 (grids of the same shape) and
  // the y-layers each thread writes alone (scatter_rows.hpp, a row being a y-layer).
  std::vector<std::vector<Node3D>> scratch;
  ScatterRows scatter_rows;
  std::size_t layer() const { return static_cast<std::size_t>(nx) * nz; }  // nodes per y-layer
};

// Constants of the scene that the stages need.
struct Setup3D {
  Material3D material;
  double V = 0.0;      // plate speed                                          [m/s]
  double h0 = 0.0;     // initial height                                       [m]
  double width = 0.0;  // specimen width in x and in z (one unit cell)         [m]
  double c_p = 0.0;    // P-wave speed                                         [m/s]
  double scale = 0.0;  // MLS force factor: vol0 D^-1 = 4 vol0 / dx^2          [m]
  PlateContact contact = PlateContact::bonded;
  double top_y(double t) const { return h0 - V * t; }
};

struct State3D {
  Setup3D setup;
  Particles3D particles;
  Grid3D grid;
  Clock clock;
  StepMeasure measure;  // x_min/x_max unused (x is periodic)
  // One per thread, combined in thread order: the plates' impulses of each thread's layers and
  // the measure of each thread's particles.
  std::vector<PlateImpulses> partial_impulses;
  std::vector<StepMeasure> partial_measures;
};

}  // namespace compaction
