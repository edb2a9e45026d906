// The stages of one explicit MPM time step, in the order step.cpp calls them.
#pragma once

#include "state.hpp"
#include "thread_pool.hpp"

namespace compaction {

// Particles to grid: mass, momentum and (MLS) stress impulse on the nodes of the rows that can
// carry mass; threads scatter into the grid on their own rows and into their scratch arrays
// near shared rows, which are then summed (scatter_rows.hpp).
void p2g(State& s, double dt, ThreadPool& pool);

// Grid velocities from momenta; rigid plates and side walls; the plates' reaction impulses.
void grid_update(State& s, ThreadPool& pool);

// Grid to particles: velocity, affine field, position, deformation gradient, return mapping and
// Kirchhoff stress; measures what the stability checks and the next time step need.
void g2p(State& s, double dt, ThreadPool& pool);

// CFL time step on the P-wave speed plus the fastest particle: cfl * dx / (c_P + |v|max).
double stable_dt(const State& s, double cfl);

}  // namespace compaction
