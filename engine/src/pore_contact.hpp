// Contact across closing pores with two velocity fields (pore_contact = split_fields).
//
// With one velocity field, the two faces of a closing pore interact as soon as their particles
// share grid nodes, one to three cells before the solid meets: the pore stops closing early
// and the compacted zone keeps voids (docs/engine.md, "Pore contact"). Here a node keeps two
// fields where faces of opposite normals meet on it, and merges them once it is full:
// - every particle carries the unit normal of its nearest pore face, pointing from the pore
//   into the solid (zero in a column without pores), set by the scene builder and carried with
//   the material as a normal is (n <- n - dt C^T n, renormalised: n follows F^-T);
// - p2g first sums w_ip n_p on each node (the node's normal); a particle belongs to the node's
//   second field when its normal opposes the node's (second_field below), else to the first.
//   Inside the solid the normals agree, or the node is full and merged; across an open gap the
//   two faces point towards each other and the heavier side sets the node's normal;
// - the grid update (grid_update.cpp) treats a node with both fields as two nodes, each with
//   its own velocity and the plates acting on each, while its mass is below kMergeCoverage of a
//   full node (rho dx^2), and as one node from then on (the sum; both fields take its
//   velocity): once the gap is closed the faces move together, as one field moves them;
// - g2p reads each particle's velocity at a node from the field p2g put it in (same test, same
//   normals: positions do not change in between).
// The partition follows the field-gradient partitioning of Homel and Herbold (2017), with the
// face normal as the field's gradient; contact is detected by the node's filling, as by the
// nodal volume of Lemiale et al. (2010) and Nairn (2013). Mass and momentum are conserved: the
// two fields of a node hold what one field would, split in two.
#pragma once

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

}  // namespace compaction::pore_contact
