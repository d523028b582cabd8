#include "core/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace colony {

namespace {
std::atomic<int> g_level{static_cast<int>(LogLevel::kInfo)};
std::mutex g_mutex;
}  // namespace

void SetLogLevel(LogLevel level) { g_level = static_cast<int>(level); }
LogLevel GetLogLevel() { return static_cast<LogLevel>(g_level.load()); }

void Log(LogLevel level, const std::string& message) {
  if (static_cast<int>(level) > g_level.load()) return;
  static const char* kNames[] = {"error", "warning", "info", "debug"};
  std::lock_guard lock(g_mutex);
  std::fprintf(stderr, "colony: %s: %s\n", kNames[static_cast<int>(level)], message.c_str());
}

}  // namespace colony
