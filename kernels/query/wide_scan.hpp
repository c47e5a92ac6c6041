// The support of a large vertex set by the SIMD support kernel (internal), for GJK's supports
// (query.cpp) and time of impact's scans of a translating body (impact.cpp).
#pragma once

namespace minksum::detail {

/// From this many vertices on, a support scan goes to the SIMD kernel; below it, the kernel's
/// set-up and lane reduction cost more than a plain loop (callgrind, AVX2).
constexpr int kWideScan = 24;

/// The first of the n vertices (arrays x, y, z) highest along (nx, ny, nz): its height into
/// `top` and its index into `arg`. Out of line, so that a small set's plain loop stays lean.
void wide_scan(const double* x, const double* y, const double* z, int n, double nx, double ny, double nz,
               double& top, int& arg);

}  // namespace minksum::detail
