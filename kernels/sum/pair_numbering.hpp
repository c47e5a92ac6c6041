// The vertices of a sum as pairs (i, j) of operand vertices, numbered in (i, j) order: shared
// by the overlay (overlay.cpp) and the assembler of the reference path and the corrector
// (assemble.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace minksum::detail {

/// The number of set bits (without the POPCNT instruction the baseline build may not assume:
/// the compiler's builtin is then a library call).
inline int bit_count(std::uint64_t x) {
  x = x - ((x >> 1) & 0x5555555555555555ull);
  x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
  x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0full;
  return int((x * 0x0101010101010101ull) >> 56);
}

/// The vertices of a sum, pairs (i, j), numbered in (i, j) order. While the loops are written
/// each pair is stored as a code; once all are known the codes become vertex indices. Pairs
/// live as bits in one row per vertex of A, and their indices in a table by code, when that
/// table holds at most kDenseCodes (operands of up to some hundreds of vertices each); else in
/// a hash table sorted by i at the end.
class PairNumbering {
 public:
  static constexpr size_t kDenseCodes = size_t(1) << 18;  // 1 MB of indices, 32 KB of rows
  /// Starts a sum of operands with nva and nvb vertices, whose loops hold about `entries` pairs.
  void reset(int nva, int nvb, size_t entries);
  /// The code of pair (i, j), registering it.
  int code(int i, int j) {
    if (dense_) {
      rows_[size_t(unsigned(i) * words_ + unsigned(j >> 6))] |= std::uint64_t(1) << (j & 63);
      return i << shift_b_ | j;
    }
    return hashed(i, j);
  }
  /// Whether the pair of code x comes before that of code y in (i, j) order.
  bool less(int x, int y) const { return dense_ ? x < y : key_[size_t(x)] < key_[size_t(y)]; }
  /// The number of distinct pairs.
  int count() const;
  /// Calls emit(k, i, j) for the pairs in (i, j) order and turns the codes in [codes, codes + n)
  /// into their indices k.
  template <class Emit>
  void finish(int* codes, size_t n, Emit&& emit);

 private:
  int hashed(int i, int j);
  void grow();
  bool dense_ = true;
  int nva_ = 0, shift_b_ = 0;
  unsigned words_ = 0;  // (not size_t: a store to a row, a 64-bit integer, would make code() reload it)
  std::vector<std::uint64_t> rows_;
  std::vector<int> index_;  // by code: the pair's index (written for the pairs there are)
  // Hash mode: the keys i 2^32 + j by code, the table (open addressing), and the sort by i.
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
  std::vector<std::uint64_t> key_, slot_key_;
  std::vector<int> slot_code_, bucket_, fill_, order_;
  int codes_ = 0;
  unsigned mask_ = 0, shift_ = 58;  // table size - 1; 64 - log2(size)
};

template <class Emit>
void PairNumbering::finish(int* codes, size_t n, Emit&& emit) {
  if (dense_) {  // the rows in (i, j) order; each pair's index noted at its code
    int v = 0;
    for (size_t w = 0; w < rows_.size(); ++w) {
      const int i = int(w / words_), base = int(w % words_) * 64;
      for (std::uint64_t bits = rows_[w]; bits; bits &= bits - 1) {
        const int j = base + __builtin_ctzll(bits);
        index_[size_t(i << shift_b_ | j)] = v;
        emit(v++, i, j);
      }
    }
    for (size_t k = 0; k < n; ++k) codes[k] = index_[size_t(codes[k])];
    return;
  }
  // The codes counted by i, then sorted by j within one i by insertion (a few per i).
  const int V = codes_;
  bucket_.assign(size_t(nva_) + 1, 0), order_.resize(size_t(V)), index_.resize(size_t(V));
  for (int c = 0; c < V; ++c) ++bucket_[size_t(key_[size_t(c)] >> 32) + 1];
  for (int i = 0; i < nva_; ++i) bucket_[i + 1] += bucket_[i];
  fill_.assign(bucket_.begin(), bucket_.end() - 1);
  for (int c = 0; c < V; ++c) {
    const int i = int(key_[size_t(c)] >> 32), lo = bucket_[i];
    int at = fill_[i]++;
    for (; at > lo && key_[size_t(order_[at - 1])] > key_[size_t(c)]; --at) order_[at] = order_[at - 1];
    order_[at] = c;
  }
  for (int v = 0; v < V; ++v) {
    const std::uint64_t key = key_[size_t(order_[v])];
    index_[size_t(order_[v])] = v;
    emit(v, int(key >> 32), int(key & 0xffffffffu));
  }
  for (size_t k = 0; k < n; ++k) codes[k] = index_[size_t(codes[k])];
}

}  // namespace minksum::detail
