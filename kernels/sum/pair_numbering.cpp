// PairNumbering's storage: dense rows of bits for small operands, a hash table for large ones.
#include "sum/pair_numbering.hpp"

namespace minksum::detail {

void PairNumbering::reset(int nva, int nvb, size_t entries) {
  nva_ = nva, shift_b_ = 0;
  while ((1 << shift_b_) < nvb) ++shift_b_;
  words_ = unsigned(nvb + 63) / 64;
  dense_ = (size_t(nva) << shift_b_) <= kDenseCodes;
  if (dense_) {
    rows_.assign(size_t(nva) * words_, 0);
    if (index_.size() < size_t(nva) << shift_b_) index_.resize(size_t(nva) << shift_b_);
    return;
  }
  codes_ = 0;
  if (key_.size() < entries) key_.resize(entries);
  unsigned size = 64;  // twice the vertices at most (each is in three loops or more)
  for (shift_ = 58; 3 * size < 2 * entries; size *= 2) --shift_;
  slot_key_.assign(size, kEmpty), slot_code_.resize(size), mask_ = size - 1;
}

int PairNumbering::hashed(int i, int j) {
  // Open addressing on the key (i, j) (Fibonacci hashing), grown at half load.
  const std::uint64_t key = std::uint64_t(i) << 32 | std::uint64_t(unsigned(j));
  unsigned h = unsigned((key * 0x9E3779B97F4A7C15ull) >> shift_);
  for (;; h = (h + 1) & mask_) {
    if (slot_key_[h] == key) return slot_code_[h];
    if (slot_key_[h] == kEmpty) break;
  }
  if (key_.size() <= size_t(codes_)) key_.resize(2 * size_t(codes_) + 64);
  slot_key_[h] = key, slot_code_[h] = codes_, key_[size_t(codes_)] = key;
  if (2 * unsigned(++codes_) > mask_) grow();
  return codes_ - 1;
}

void PairNumbering::grow() {
  const unsigned size = 2 * (mask_ + 1);
  slot_key_.assign(size, kEmpty), slot_code_.resize(size), mask_ = size - 1, --shift_;
  for (int c = 0; c < codes_; ++c) {
    unsigned g = unsigned((key_[size_t(c)] * 0x9E3779B97F4A7C15ull) >> shift_);
    while (slot_key_[g] != kEmpty) g = (g + 1) & mask_;
    slot_key_[g] = key_[size_t(c)], slot_code_[g] = c;
  }
}

int PairNumbering::count() const {
  if (!dense_) return codes_;
  int n = 0;
  for (const std::uint64_t w : rows_) n += bit_count(w);
  return n;
}

}  // namespace minksum::detail
