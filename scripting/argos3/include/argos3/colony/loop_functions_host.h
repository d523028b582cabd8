// ARGoS compatibility layer (Colony), internal: the Colony loop functions
// that run ARGoS loop functions (REGISTER_LOOP_FUNCTIONS registers one per
// class).
#pragma once

#include <memory>
#include <type_traits>
#include <vector>

#include "argos3/colony/controller_host.h"
#include "argos3/core/simulator/loop_functions.h"
#include "core/loop_functions.h"

namespace argos::internal {

class LoopFunctionsHost : public colony::LoopFunctions, public RngOwner {
 public:
  using Factory = std::unique_ptr<CLoopFunctions> (*)();
  // `draws_floor`: the class overrides GetFloorColor.
  LoopFunctionsHost(Factory factory, bool draws_floor);
  ~LoopFunctionsHost() override;

  void Init(const colony::Params& params) override;
  void PreStep() override;
  void PostStep() override;
  bool IsExperimentFinished() override;
  bool DrawsFloor() const override { return draws_floor_; }
  colony::Color FloorColor(double x, double y) override;
  void Destroy() override;

  UInt64 NextRngSeed() override { return stream_.NextU64(); }
  void Keep(std::unique_ptr<CRandom::CRNG> rng) override;

 private:
  Factory factory_;
  bool draws_floor_;
  std::unique_ptr<CSpace> space_;
  std::unique_ptr<CLoopFunctions> user_;
  colony::RandomStream stream_;
  std::vector<std::unique_ptr<CRandom::CRNG>> rngs_;
  bool destroyed_ = false;
};

template <class C>
class LoopFunctionsHostFor final : public LoopFunctionsHost {
 public:
  LoopFunctionsHostFor()
      : LoopFunctionsHost([]() -> std::unique_ptr<CLoopFunctions> { return std::make_unique<C>(); },
                          // Whether C overrides GetFloorColor.
                          !std::is_same_v<decltype(&C::GetFloorColor),
                                          CColor (CLoopFunctions::*)(const CVector2&)>) {}
};

}  // namespace argos::internal
