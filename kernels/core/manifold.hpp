// The closed-manifold check of polygon loops (internal), shared by the polytope builders and the
// sum's assembler.
#pragma once

#include <vector>

namespace minksum::detail {

/// Pairs each directed edge of the loops with its reverse. Loop f holds the vertices
/// loop_vertex[loop_start[f] .. loop_start[f + 1]) (loop_start[0] = 0; vertices in
/// [0, vertices)); the edge at slot k goes from loop_vertex[k] to the next vertex of its loop.
/// False unless every directed edge appears once and its reverse once: a closed 2-manifold.
/// Then, if `twin` is given, twin[k] is the slot of slot k's reverse. The scratch only grows (a
/// caller that reuses it allocates once).
bool pair_edges(const int* loop_start, int loops, const int* loop_vertex, int vertices, int* twin,
                std::vector<int>& scratch);

}  // namespace minksum::detail
