// The kinds of query that fill a ProximityCache (internal): a cache filled by one kind starts
// the others cold.
#pragma once

namespace minksum::detail {

enum CacheKind : unsigned { kCacheBoxBox = 1, kCacheConvex = 2, kCacheMesh = 3, kCacheSegment = 4, kCacheMeshShape = 5 };

}  // namespace minksum::detail
