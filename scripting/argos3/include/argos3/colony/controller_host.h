// ARGoS compatibility layer (Colony), internal: the Colony controller that
// runs an ARGoS controller (REGISTER_CONTROLLER registers one per class).
// It builds the configuration tree from the <params>, hands the controller
// its devices in ARGoS's units, reads the sensors before each ControlStep,
// and turns ARGoS exceptions into Colony's errors.
#pragma once

#include <memory>
#include <string>
#include <typeinfo>
#include <vector>

#include "argos3/core/control_interface/ci_controller.h"
#include "argos3/core/utility/math/rng.h"
#include "core/control_interface.h"
#include "core/registry.h"

namespace argos::internal {

// Where CRandom::CreateRNG draws from: the robot or loop functions whose code
// runs on this thread.
class RngOwner {
 public:
  // A seed for a new generator, drawn from the owner's stream.
  virtual UInt64 NextRngSeed() = 0;
  // Keeps a generator alive as long as the owner.
  virtual void Keep(std::unique_ptr<CRandom::CRNG> rng) = 0;

 protected:
  ~RngOwner() = default;
};

// Makes `owner` the current one on this thread for the scope's lifetime, and
// writes the LOG lines left unfinished when it ends.
class OwnerScope {
 public:
  explicit OwnerScope(RngOwner* owner);
  ~OwnerScope();
  OwnerScope(const OwnerScope&) = delete;
  OwnerScope& operator=(const OwnerScope&) = delete;

 private:
  RngOwner* previous_;
};

class ControllerHost : public colony::Controller, public RngOwner {
 public:
  using Factory = std::unique_ptr<CCI_Controller> (*)();
  explicit ControllerHost(Factory factory);
  ~ControllerHost() override;

  void Init(const colony::Params& params) override;
  void ControlStep() override;
  void Reset() override;
  void Destroy() override;

  // The ARGoS controller (null before Init).
  CCI_Controller* user() const { return user_.get(); }

  // For CCI_Controller.
  CCI_Sensor* FindSensor(const std::string& label, const std::type_info& wanted);
  CCI_Actuator* FindActuator(const std::string& label);
  bool HasDevice(const std::string& label, bool sensor) const;

  UInt64 NextRngSeed() override { return rng().NextU64(); }
  void Keep(std::unique_ptr<CRandom::CRNG> rng) override;

 private:
  struct Devices;

  Factory factory_;
  std::unique_ptr<CCI_Controller> user_;
  std::unique_ptr<Devices> devices_;
  std::vector<std::unique_ptr<CRandom::CRNG>> rngs_;
};

template <class C>
class ControllerHostFor final : public ControllerHost {
 public:
  ControllerHostFor()
      : ControllerHost([]() -> std::unique_ptr<CCI_Controller> { return std::make_unique<C>(); }) {}
};

}  // namespace argos::internal
