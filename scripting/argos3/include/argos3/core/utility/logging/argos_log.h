// ARGoS compatibility layer (Colony): the LOG and LOGERR streams. A line is
// written when it ends (std::endl), whole, through Colony's log (standard
// error, safe from the threads robots run on): LOG lines as information,
// LOGERR lines as errors (kept by `colony run --quiet`). A line left
// unfinished at the end of a controller's or loop functions' step is written
// then. RLOG and RLOGERR start the line with the robot's id.
#pragma once

#include <iostream>
#include <sstream>
#include <string>

#include "argos3/core/utility/datatypes/datatypes.h"

namespace argos {

class CARGoSLog {
 public:
  enum class Level { kInfo, kError };
  explicit CARGoSLog(Level level) : level_(level) {}
  CARGoSLog(const CARGoSLog&) = delete;
  CARGoSLog& operator=(const CARGoSLog&) = delete;

  // std::endl writes the line; other manipulators apply to it.
  CARGoSLog& operator<<(std::ostream& (*manipulator)(std::ostream&));
  template <typename T>
  CARGoSLog& operator<<(const T& value) {
    Buffer() << value;
    return *this;
  }
  // Writes the unfinished line of this thread, if any.
  void Flush();

 private:
  // This thread's line in the making.
  std::ostringstream& Buffer();

  Level level_;
};

extern CARGoSLog LOG;
extern CARGoSLog LOGERR;

}  // namespace argos

#define RLOG argos::LOG << "[" << GetId() << "] "
#define RLOGERR argos::LOGERR << "[" << GetId() << "] "
