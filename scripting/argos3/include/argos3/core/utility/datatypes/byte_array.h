// ARGoS compatibility layer (Colony): CByteArray, the payload of
// range-and-bearing messages. `<<` appends a value at the back, `>>` takes one
// from the front. Integers travel in network byte order (big-endian) as in
// ARGoS; strings end with a zero byte; a float or double travels as its
// IEEE-754 bits in network byte order (ARGoS uses its own encoding there, so
// doubles do not travel between the two; integers and strings do).
#pragma once

#include <algorithm>
#include <cstring>
#include <iostream>
#include <string>
#include <type_traits>
#include <vector>

#include "argos3/core/utility/datatypes/datatypes.h"

namespace argos {

class CByteArray {
 public:
  CByteArray() = default;
  CByteArray(const UInt8* buffer, size_t size) : bytes_(buffer, buffer + size) {}
  explicit CByteArray(size_t size, UInt8 value = 0) : bytes_(size, value) {}

  size_t Size() const { return bytes_.size(); }
  void Resize(size_t size, UInt8 value = 0) { bytes_.resize(size, value); }
  void Swap(CByteArray& other) { bytes_.swap(other.bytes_); }
  bool Empty() const { return bytes_.empty(); }
  const UInt8* ToCArray() const { return bytes_.data(); }
  UInt8* ToCArray() { return bytes_.data(); }
  // Removes every byte.
  void Clear() { bytes_.clear(); }
  // Sets every byte to 0 (the size stays).
  void Zero() { std::fill(bytes_.begin(), bytes_.end(), UInt8{0}); }

  UInt8& operator[](size_t i) { return bytes_[i]; }
  UInt8 operator[](size_t i) const { return bytes_[i]; }
  bool operator==(const CByteArray& other) const { return bytes_ == other.bytes_; }
  bool operator!=(const CByteArray& other) const { return bytes_ != other.bytes_; }

  // Appends `size` bytes.
  CByteArray& AddBuffer(const UInt8* buffer, size_t size) {
    bytes_.insert(bytes_.end(), buffer, buffer + size);
    return *this;
  }
  // Moves the first `size` bytes into `buffer`; throws CARGoSException when
  // fewer are left.
  CByteArray& FetchBuffer(UInt8* buffer, size_t size);
  template <typename T>
  T PopFront() {
    T value;
    *this >> value;
    return value;
  }

  CByteArray& operator<<(UInt8 v) { return Append(v); }
  CByteArray& operator>>(UInt8& v) { return Take(v); }
  CByteArray& operator<<(SInt8 v) { return Append(v); }
  CByteArray& operator>>(SInt8& v) { return Take(v); }
  CByteArray& operator<<(UInt16 v) { return Append(v); }
  CByteArray& operator>>(UInt16& v) { return Take(v); }
  CByteArray& operator<<(SInt16 v) { return Append(v); }
  CByteArray& operator>>(SInt16& v) { return Take(v); }
  CByteArray& operator<<(UInt32 v) { return Append(v); }
  CByteArray& operator>>(UInt32& v) { return Take(v); }
  CByteArray& operator<<(SInt32 v) { return Append(v); }
  CByteArray& operator>>(SInt32& v) { return Take(v); }
  CByteArray& operator<<(unsigned long v) { return Append(static_cast<UInt64>(v)); }
  CByteArray& operator>>(unsigned long& v) { return TakeAs<UInt64>(v); }
  CByteArray& operator<<(signed long v) { return Append(static_cast<SInt64>(v)); }
  CByteArray& operator>>(signed long& v) { return TakeAs<SInt64>(v); }
  CByteArray& operator<<(unsigned long long v) { return Append(static_cast<UInt64>(v)); }
  CByteArray& operator>>(unsigned long long& v) { return TakeAs<UInt64>(v); }
  CByteArray& operator<<(signed long long v) { return Append(static_cast<SInt64>(v)); }
  CByteArray& operator>>(signed long long& v) { return TakeAs<SInt64>(v); }
  CByteArray& operator<<(double v) { return AppendBits<UInt64>(v); }
  CByteArray& operator>>(double& v) { return TakeBits<UInt64>(v); }
  CByteArray& operator<<(float v) { return AppendBits<UInt32>(v); }
  CByteArray& operator>>(float& v) { return TakeBits<UInt32>(v); }
  // The characters and a terminating zero byte.
  CByteArray& operator<<(const std::string& v);
  // Up to and without the next zero byte (which is removed too).
  CByteArray& operator>>(std::string& v);

  // Writes the bytes as numbers: "[ 1 2 3 ]".
  friend std::ostream& operator<<(std::ostream& os, const CByteArray& array);

 private:
  // Big-endian.
  template <typename T>
  CByteArray& Append(T value) {
    using U = std::make_unsigned_t<T>;
    const U bits = static_cast<U>(value);
    for (int shift = 8 * (static_cast<int>(sizeof(T)) - 1); shift >= 0; shift -= 8)
      bytes_.push_back(static_cast<UInt8>(bits >> shift));
    return *this;
  }
  template <typename T>
  CByteArray& Take(T& value) {
    using U = std::make_unsigned_t<T>;
    CheckAvailable(sizeof(T));
    U bits = 0;
    for (size_t i = 0; i < sizeof(T); ++i) bits = static_cast<U>(bits << 8 | bytes_[i]);
    bytes_.erase(bytes_.begin(), bytes_.begin() + sizeof(T));
    value = static_cast<T>(bits);
    return *this;
  }
  template <typename Wire, typename T>
  CByteArray& TakeAs(T& value) {
    Wire wire;
    Take(wire);
    value = static_cast<T>(wire);
    return *this;
  }
  template <typename Bits, typename F>
  CByteArray& AppendBits(F value) {
    Bits bits;
    std::memcpy(&bits, &value, sizeof bits);
    return Append(bits);
  }
  template <typename Bits, typename F>
  CByteArray& TakeBits(F& value) {
    Bits bits;
    Take(bits);
    std::memcpy(&value, &bits, sizeof value);
    return *this;
  }
  // Throws CARGoSException when fewer than `size` bytes are left.
  void CheckAvailable(size_t size) const;

  std::vector<UInt8> bytes_;
};

}  // namespace argos
