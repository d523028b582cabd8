#include "core/log.h"

#include "argos3/core/utility/logging/argos_log.h"

namespace argos {

CARGoSLog LOG(CARGoSLog::Level::kInfo);
CARGoSLog LOGERR(CARGoSLog::Level::kError);

namespace {
// One line in the making per thread and stream.
struct Line {
  std::ostringstream text;
  bool started = false;
};
thread_local Line g_lines[2];
}  // namespace

std::ostringstream& CARGoSLog::Buffer() {
  Line& line = g_lines[static_cast<int>(level_)];
  line.started = true;
  return line.text;
}

CARGoSLog& CARGoSLog::operator<<(std::ostream& (*manipulator)(std::ostream&)) {
  if (manipulator == static_cast<std::ostream& (*)(std::ostream&)>(std::endl)) {
    Buffer();
    Flush();
  } else {
    manipulator(Buffer());
  }
  return *this;
}

void CARGoSLog::Flush() {
  Line& line = g_lines[static_cast<int>(level_)];
  if (!line.started) return;
  colony::Log(level_ == Level::kError ? colony::LogLevel::kError : colony::LogLevel::kInfo,
              line.text.str());
  line.text.str("");
  line.started = false;
}

}  // namespace argos
