// A hash of simulation state (FNV-1a over the exact bits), used to check that
// the same file and seed give bit-identical runs whatever the thread count.
#pragma once

#include <cstdint>
#include <string>

#include "core/random.h"

namespace colony {

class StateHasher {
 public:
  void Add(const void* data, size_t size) { h_ = HashBytes(data, size, h_); }
  void AddDouble(double v) { Add(&v, sizeof v); }
  void AddU64(uint64_t v) { Add(&v, sizeof v); }
  uint64_t value() const { return h_; }
  static std::string Hex(uint64_t v);

 private:
  uint64_t h_ = 14695981039346656037ull;
};

}  // namespace colony
