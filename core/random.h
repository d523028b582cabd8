// Random streams. Every random draw in Colony comes from a stream owned by one
// thing (an entity, a sensor instance, a controller), seeded from the
// experiment seed and the owner's id, so results never depend on scheduling.
// Self-contained (std only): controllers may use it on a real robot too.
#pragma once

#include <cmath>
#include <cstdint>
#include <string_view>

namespace colony {

// FNV-1a over bytes; used to turn owner ids into seeds.
inline uint64_t HashBytes(const void* data, size_t size, uint64_t h = 14695981039346656037ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

inline uint64_t HashString(std::string_view s, uint64_t h = 14695981039346656037ull) {
  return HashBytes(s.data(), s.size(), h);
}

// xoshiro256++ (32 bytes of state), seeded through SplitMix64.
class RandomStream {
 public:
  RandomStream() : RandomStream(0) {}
  explicit RandomStream(uint64_t seed) {
    for (auto& word : s_) word = SplitMix(seed);
  }

  // The stream of `owner` (an entity id) for `purpose` (a sensor label...).
  static RandomStream For(uint64_t experiment_seed, std::string_view owner,
                          std::string_view purpose) {
    return For(experiment_seed, owner, purpose, "");
  }
  // The stream of purpose `purpose` + `purpose_tail` (e.g. "sensor/" and a
  // device's label), without building that string: the hash runs over the
  // bytes in order, so the stream is the same.
  static RandomStream For(uint64_t experiment_seed, std::string_view owner,
                          std::string_view purpose, std::string_view purpose_tail) {
    return RandomStream(SeedFor(experiment_seed, owner, purpose, purpose_tail));
  }
  // The seed of that stream: RandomStream(SeedFor(...)) is For(...). Eight
  // bytes to keep instead of the stream's 32 until the owner first draws.
  static uint64_t SeedFor(uint64_t experiment_seed, std::string_view owner,
                          std::string_view purpose, std::string_view purpose_tail = "") {
    uint64_t h = HashString(owner, experiment_seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull);
    h = HashString("/", h);
    return HashString(purpose_tail, HashString(purpose, h));
  }

  uint64_t NextU64() {
    const uint64_t result = Rotl(s_[0] + s_[3], 23) + s_[0];
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = Rotl(s_[3], 45);
    return result;
  }

  // Uniform in [0, 1).
  double Uniform() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }
  double Uniform(double min, double max) { return min + (max - min) * Uniform(); }
  // Uniform integer in [0, n).
  uint64_t UniformInt(uint64_t n) { return n == 0 ? 0 : NextU64() % n; }
  bool Bernoulli(double p) { return Uniform() < p; }
  double Gaussian(double mean, double std_dev) {
    // Box-Muller; the second value is dropped to keep the state at 32 bytes.
    double u1 = Uniform();
    while (u1 <= 0.0) u1 = Uniform();
    const double u2 = Uniform();
    return mean + std_dev * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  static uint64_t Rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static uint64_t SplitMix(uint64_t& state) {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  uint64_t s_[4];
};

}  // namespace colony
