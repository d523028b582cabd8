#include "argos3/core/utility/math/rng.h"

#include <cmath>

#include "argos3/colony/controller_host.h"
#include "argos3/core/utility/configuration/argos_exception.h"
#include "argos3/core/utility/logging/argos_log.h"

namespace argos {

namespace {
// The robot or loop functions whose code runs on this thread.
thread_local internal::RngOwner* g_owner = nullptr;
}  // namespace

namespace internal {

OwnerScope::OwnerScope(RngOwner* owner) : previous_(g_owner) { g_owner = owner; }

OwnerScope::~OwnerScope() {
  g_owner = previous_;
  LOG.Flush();
  LOGERR.Flush();
}

}  // namespace internal

CRandom::CRNG* CRandom::CreateRNG(const std::string& category) {
  if (category != "argos") {
    THROW_ARGOSEXCEPTION("CRandom::CreateRNG(\""
                         << category
                         << "\"): no such category; Colony's "
                            "ARGoS compatibility layer provides only \"argos\"");
  }
  if (g_owner == nullptr) {
    THROW_ARGOSEXCEPTION(
        "CRandom::CreateRNG(\"argos\") was called outside a controller's or loop functions' code "
        "(call it from Init, ControlStep, PreStep...), so there is no robot whose random stream it "
        "could draw from");
  }
  const UInt64 seed = g_owner->NextRngSeed();
  std::unique_ptr<CRNG> rng(new CRNG(colony::RandomStream(seed), seed));
  CRNG* raw = rng.get();
  g_owner->Keep(std::move(rng));
  return raw;
}

SInt32 CRandom::CRNG::Uniform(const CRange<SInt32>& range) {
  if (range.GetMax() <= range.GetMin()) return range.GetMin();
  const UInt64 span = static_cast<UInt64>(static_cast<SInt64>(range.GetMax()) - range.GetMin());
  return static_cast<SInt32>(range.GetMin() + static_cast<SInt64>(stream_.UniformInt(span)));
}

UInt32 CRandom::CRNG::Uniform(const CRange<UInt32>& range) {
  if (range.GetMax() <= range.GetMin()) return range.GetMin();
  return range.GetMin() + static_cast<UInt32>(stream_.UniformInt(range.GetMax() - range.GetMin()));
}

Real CRandom::CRNG::Exponential(Real mean) { return -mean * std::log(1 - stream_.Uniform()); }

Real CRandom::CRNG::Rayleigh(Real sigma) {
  return sigma * std::sqrt(-2 * std::log(1 - stream_.Uniform()));
}

Real CRandom::CRNG::Lognormal(Real sigma, Real mu) { return std::exp(stream_.Gaussian(mu, sigma)); }

UInt32 CRandom::CRNG::Poisson(Real mean) {
  if (!(mean > 0)) return 0;
  if (mean < 30) {
    // Multiply uniforms until the product falls below e^-mean (Knuth).
    const Real limit = std::exp(-mean);
    UInt32 k = 0;
    for (Real product = stream_.Uniform(); product > limit; product *= stream_.Uniform()) ++k;
    return k;
  }
  // Transformed rejection with squeeze (Hormann 1993, "PTRS"), exact for any mean.
  const Real root = std::sqrt(mean);
  const Real log_mean = std::log(mean);
  const Real b = 0.931 + 2.53 * root;
  const Real a = -0.059 + 0.02483 * b;
  const Real inv_alpha = 1.1239 + 1.1328 / (b - 3.4);
  const Real v_r = 0.9277 - 3.6224 / (b - 2);
  while (true) {
    const Real u = stream_.Uniform() - 0.5;
    const Real v = stream_.Uniform();
    const Real us = 0.5 - std::fabs(u);
    const Real k = std::floor((2 * a / us + b) * u + mean + 0.43);
    if (us >= 0.07 && v <= v_r) return static_cast<UInt32>(k);
    if (k < 0 || (us < 0.013 && v > us)) continue;
    if (std::log(v) + std::log(inv_alpha) - std::log(a / (us * us) + b) <=
        -mean + k * log_mean - std::lgamma(k + 1))
      return static_cast<UInt32>(k);
  }
}

}  // namespace argos
