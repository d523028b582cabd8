// ARGoS compatibility layer (Colony): the range-and-bearing emitter. The
// payload has GetSize() bytes (the experiment file's data_size) and is sent
// every tick until changed; ClearData() sets it to zeros (it keeps being
// sent, as in ARGoS). SetData with a payload of another size, or an index
// beyond it, throws CARGoSException.
#pragma once

#include "argos3/core/control_interface/ci_actuator.h"
#include "argos3/core/utility/datatypes/byte_array.h"

namespace argos {

class CCI_RangeAndBearingActuator : public CCI_Actuator {
 public:
  ~CCI_RangeAndBearingActuator() override = default;
  size_t GetSize() const { return data_.Size(); }
  virtual void SetData(const CByteArray& data) = 0;
  virtual void SetData(size_t index, UInt8 value) = 0;
  virtual void ClearData() = 0;

 protected:
  CByteArray data_;
};

}  // namespace argos
