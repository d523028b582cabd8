// ARGoS compatibility layer (Colony): random numbers. CRandom::CreateRNG("argos")
// called from a controller returns a generator drawing from that robot's own
// deterministic stream (seeded from the experiment's seed and the robot's
// id), so results do not depend on the thread count; called from loop
// functions, one drawing from the loop functions' stream. Only the "argos"
// category exists. The generator is owned by the robot (or loop functions).
#pragma once

#include <string>
#include <vector>

#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/core/utility/math/angles.h"
#include "argos3/core/utility/math/range.h"
#include "core/random.h"

namespace argos {

class CRandom {
 public:
  class CRNG {
   public:
    // A generator of its own, seeded with `seed`.
    explicit CRNG(UInt32 seed) { SetSeed(seed); }
    virtual ~CRNG() = default;

    UInt32 GetSeed() const { return static_cast<UInt32>(seed_); }
    // Restarts the generator from `seed`.
    void SetSeed(UInt32 seed) {
      seed_ = seed;
      start_ = stream_ = colony::RandomStream(seed);
    }
    // Restarts the generator: it draws again the numbers it drew.
    void Reset() { stream_ = start_; }

    // True with probability `p`.
    bool Bernoulli(Real p = 0.5) { return stream_.Uniform() < p; }
    // Uniform in [min, max).
    CRadians Uniform(const CRange<CRadians>& range) {
      return CRadians(stream_.Uniform(range.GetMin().GetValue(), range.GetMax().GetValue()));
    }
    Real Uniform(const CRange<Real>& range) {
      return stream_.Uniform(range.GetMin(), range.GetMax());
    }
    // Uniform integer in [min, max) (min when max <= min).
    SInt32 Uniform(const CRange<SInt32>& range);
    UInt32 Uniform(const CRange<UInt32>& range);
    // Exponential with mean `mean`.
    Real Exponential(Real mean);
    // Poisson with mean `mean`.
    UInt32 Poisson(Real mean);
    // Normal with standard deviation `std_dev` and mean `mean` (note the order).
    Real Gaussian(Real std_dev, Real mean = 0) { return stream_.Gaussian(mean, std_dev); }
    Real Rayleigh(Real sigma);
    // exp(N(mu, sigma)).
    Real Lognormal(Real sigma, Real mu);
    // Fisher-Yates.
    template <typename T>
    void Shuffle(std::vector<T>& data) {
      for (size_t i = data.size(); i > 1; --i) std::swap(data[i - 1], data[stream_.UniformInt(i)]);
    }
    UInt32 Uniform32bit() { return static_cast<UInt32>(stream_.NextU64() >> 32); }

   private:
    friend class CRandom;
    explicit CRNG(const colony::RandomStream& stream, UInt64 seed)
        : seed_(seed), stream_(stream), start_(stream) {}

    UInt64 seed_ = 0;
    colony::RandomStream stream_;
    colony::RandomStream start_;
  };

  // A generator of the "argos" category, drawing from the stream of the
  // robot (or loop functions) whose code is running; throws CARGoSException
  // for another category or when called outside a controller's or loop
  // functions' code.
  static CRNG* CreateRNG(const std::string& category);
};

}  // namespace argos
