// The box-box query (box_query.cpp) for prepared boxes under poses; internal.
#pragma once

#include <minksum/query.hpp>

namespace minksum::detail {

/// The proximity of two checked boxes to the fields `want` asks for, the patch's witnesses where
/// asked, through the active set of `cache` if given (a box-box cache, else it starts cold).
void box_answer(const Box& a, const Box& b, ProximityCache* cache, Proximity& out, Want want);

}  // namespace minksum::detail
