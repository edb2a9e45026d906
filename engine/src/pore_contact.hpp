// Contact across closing pores with two velocity fields (pore_contact = split_fields).
//
// With one velocity field, the two faces of a closing pore interact as soon as their particles
// share grid nodes, one to three cells before the solid meets: the pore stops closing early
// and the compacted zone keeps voids (docs/engine.md, "Pore contact"). Here a node keeps two
// fields where faces of opposite normals meet on it, and merges them once it is full:
// - every particle carries the unit normal of its nearest pore face, pointing from the pore
//   into the solid (zero in a column without pores), set by the scene builder and carried with
//   the material as a normal is (n <- n - dt C^T n, renormalised: n follows F^-T);
// - a particle belongs to a node's second field when its normal opposes the node's normal, the
//   sum of w_ip n_p over the node's particles (second_field below), else to the first. Inside
//   the solid the normals agree, or the node is full and its fields are merged; across an open
//   gap the two faces point towards each other and the heavier side sets the node's normal;
// - so the two fields of a node differ from its one field only where the node is not full and
//   its particles' normals do not all lie within 90 degrees of each other (with all of them
//   within 90 degrees, no particle's normal opposes their weighted sum). p2g scatters one
//   field, and with it which of eight 90-degree windows of directions each node's normals lie
//   outside of (outside_windows). Then, on the nodes that are not full and whose normals share
//   no window (may_oppose), it sums the node normals and scatters the particles of those nodes
//   again, into the two fields (p2g_split_fields.cpp);
// - the grid update (grid_update.cpp) treats a node with both fields as two nodes, each with
//   its own velocity and the plates acting on each, while its mass is below kMergeCoverage of a
//   full node (rho dx^2), and as one node from then on (the sum; both fields take its
//   velocity): once the gap is closed the faces move together, as one field moves them;
// - g2p reads each particle's velocity at a node from the field p2g put it in (its field bits).
// The partition follows the field-gradient partitioning of Homel and Herbold (2017), with the
// face normal as the field's gradient; contact is detected by the node's filling, as by the
// nodal volume of Lemiale et al. (2010) and Nairn (2013). Mass and momentum are conserved: the
// two fields of a node hold what one field would, split in two.
#pragma once

#include <cmath>
#include <cstdint>

namespace compaction::pore_contact {

// The share of a full node's mass from which a node's two fields are one. A node midway in a
// gap of width g between two flat faces (quadratic B-spline, particles on their lattice) holds
// 1 of a full node's mass at g = 0, 0.92 at g = 0.1 dx, 0.81 at 0.25 dx, 0.64 at 0.5 dx and
// 0.33 at one cell: 0.9 merges when the gap is about an eighth of a cell, a quarter of the
// particle spacing at 2 particles per cell. Inside a strut the normals of its two halves
// oppose; a node reaches both halves only within 1.5 dx of the strut's middle, so at least
// t/2 - 1.5 dx inside its surface: 0.75 dx at 4.5 cells across (the default preset), where it
// holds 0.93 and is merged. At kSplitFieldsMinStrutCells (3) a node 0.5 dx inside holds 0.83
// and reaches the far half's nearest particles with the kernel's tail (weight 0.03): those
// move there with their own field, a weak seam that finer grids remove.
inline constexpr double kMergeCoverage = 0.9;

// Whether particle normal (nx, ny) belongs to the second field of a node of normal (mx, my).
inline bool second_field(double nx, double ny, double mx, double my) {
  return nx * mx + ny * my < 0.0;
}

// The eight windows of normals: window k holds the directions from 45 k to 45 k + 90 degrees,
// ends included. Normals within one window are within 90 degrees of each other, so none of them
// opposes their weighted sum (second_field): a node whose normals share a window has one field.
// Any normals within 45 degrees of each other share one, as do the faces of a pore's corner.
// The windows a normal (nx, ny) lies outside of, bit k for window k: comparisons of nx and ny
// with 0 and with each other, exact, and arithmetic without branches, so that it vectorises
// across a block. 0 for a zero normal (a column without pores), which lies in every window.
inline std::int64_t outside_windows(double nx, double ny) {
  const bool right = nx >= 0.0, left = nx <= 0.0, up = ny >= 0.0, down = ny <= 0.0;
  const bool above_diagonal = ny >= nx, below_diagonal = ny <= nx;              // y = x
  const bool above_anti = ny >= -nx, below_anti = ny <= -nx;                    // y = -x
  const std::int64_t inside = (right && up ? 1 : 0) |                           // [0, 90]
                              (above_diagonal && above_anti ? 2 : 0) |          // [45, 135]
                              (left && up ? 4 : 0) |                            // [90, 180]
                              (below_anti && above_diagonal ? 8 : 0) |          // [135, 225]
                              (left && down ? 16 : 0) |                         // [180, 270]
                              (below_diagonal && below_anti ? 32 : 0) |         // [225, 315]
                              (right && down ? 64 : 0) |                        // [270, 360]
                              (below_diagonal && above_anti ? 128 : 0);         // [315, 45]
  return ~inside & 255;
}

// Whether normals that lie outside of `windows` (outside_windows, or'ed) may put some of them in
// a node's second field: not when they share a window.
inline bool may_oppose(unsigned windows) { return windows == 255; }

}  // namespace compaction::pore_contact
