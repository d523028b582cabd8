// Logging to standard error, safe from any thread. Loop functions and
// plugins use it for messages a researcher should see; `colony run --quiet`
// keeps only errors.
#pragma once

#include <string>

namespace colony {

enum class LogLevel { kError = 0, kWarning = 1, kInfo = 2, kDebug = 3 };

void SetLogLevel(LogLevel level);
LogLevel GetLogLevel();
// Writes "colony: <level>: message" when `level` is enabled.
void Log(LogLevel level, const std::string& message);
inline void LogWarning(const std::string& message) { Log(LogLevel::kWarning, message); }
inline void LogInfo(const std::string& message) { Log(LogLevel::kInfo, message); }

}  // namespace colony
