// The sanitizer build's stand-in for alloc_count.cpp: AddressSanitizer owns malloc, so the
// allocator is not replaced and allocations are not counted (reported as -1).
namespace minksum::haptics {
long allocation_count() { return -1; }
}  // namespace minksum::haptics
