// The stages of one explicit MPM time step of the 3D column, in the order step_3d.cpp calls
// them. Every loop runs over contiguous arrays in a fixed order, each thread of the pool over a
// fixed share, and what threads share is combined in thread order (deterministic for a
// number of threads).
#pragma once

#include "state_3d.hpp"
#include "thread_pool.hpp"

namespace compaction {

// Particles to grid: mass, momentum and MLS stress impulse on the nodes of the y-layers that
// can carry mass (APIC: the affine momentum m C d).
void p2g_3d(State3D& s, double dt, ThreadPool& pool);

// Grid velocities from momenta; the rigid plates and their reaction impulses.
void grid_update_3d(State3D& s, ThreadPool& pool);

// Grid to particles: velocity, affine field, position (x, z wrapped), deformation gradient,
// return mapping and Kirchhoff stress; measures what the next step needs.
void g2p_3d(State3D& s, double dt, ThreadPool& pool);

// CFL time step on the P-wave speed plus the fastest particle: cfl dx / (c_P + |v|max).
double stable_dt_3d(const State3D& s, double cfl);

}  // namespace compaction
