// The box-box query (box_query.cpp); internal.
#pragma once

#include <minksum/query.hpp>

namespace minksum::detail {

/// The proximity of two checked boxes to the fields `want` asks for (the patch aside), from the
/// active set `active` (0: cold), which it leaves at the answer's; `warm`: the answer came from it.
void box_query(const Box& a, const Box& b, Proximity& out, Want want, unsigned& active, bool& warm);

}  // namespace minksum::detail
