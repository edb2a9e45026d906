// The second part of P2G with two velocity fields (pore_contact = split_fields).
#pragma once

#include "state.hpp"
#include "thread_pool.hpp"

namespace compaction {

// After p2g has scattered one field and the windows its normals lie outside of: lists the nodes
// whose two fields may differ from their one field (not full, normals that may oppose;
// pore_contact.hpp), sums the node normals there and scatters the particles that reach them
// again, each pair into the first or the second field of a listed node; sets every particle's
// field bits for g2p.
void split_fields(State& s, double dt, ThreadPool& pool);

}  // namespace compaction
