// The closed-manifold check shared by the sum and the polytope builders (see manifold.hpp).
#include "core/manifold.hpp"

#include <cstddef>

namespace minksum::detail {

bool pair_edges(const int* loop_start, int loops, const int* loop_vertex, int vertices, int* twin,
                std::vector<int>& scratch) {
  // The slots grouped by their tail vertex (a counting sort: a few per vertex), so that each
  // edge's reverse is found by a short scan of its head's slots.
  const int slots = loop_start[loops];
  scratch.assign(std::size_t(vertices) + 1 + 2 * std::size_t(slots), 0);
  int* start = scratch.data();
  int* head = start + vertices + 1;  // per slot: its edge's head
  int* by_tail = head + slots;       // slots ordered by tail
  for (int f = 0; f < loops; ++f)
    for (int k = loop_start[f]; k < loop_start[f + 1]; ++k) {
      head[k] = loop_vertex[k + 1 < loop_start[f + 1] ? k + 1 : loop_start[f]];
      ++start[loop_vertex[k] + 1];
    }
  for (int v = 0; v < vertices; ++v) start[v + 1] += start[v];
  for (int k = 0; k < slots; ++k) by_tail[start[loop_vertex[k]]++] = k;
  for (int v = vertices; v > 0; --v) start[v] = start[v - 1];  // back to the group starts
  start[0] = 0;
  for (int k = 0; k < slots; ++k) {
    const int u = loop_vertex[k], v = head[k];
    if (u == v) return false;  // a repeated vertex: no edge
    int forward = 0, reverse = 0, found = -1;
    for (int s = start[u]; s < start[u + 1]; ++s) forward += head[by_tail[s]] == v;
    for (int s = start[v]; s < start[v + 1]; ++s)
      if (head[by_tail[s]] == u) ++reverse, found = by_tail[s];
    if (forward != 1 || reverse != 1) return false;
    if (twin) twin[k] = found;
  }
  return true;
}

}  // namespace minksum::detail
