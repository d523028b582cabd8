// Test helpers shared by the media and the devices that use them.
#pragma once

#include <regex>
#include <string>
#include <vector>

#include "tests/test_util.h"

namespace colony::testing {

// The attribute names in the first column of the markdown table that follows
// `heading` in the README at `path` (relative to the source tree), up to the
// next heading: what the README documents, to compare with what is registered.
inline std::vector<std::string> ReadmeAttributes(const std::string& path,
                                                 const std::string& heading) {
  const std::string text = ReadFile(std::string(COLONY_SOURCE_DIR) + "/" + path);
  const size_t at = text.find(heading);
  EXPECT_NE(at, std::string::npos) << heading << " not in " << path;
  std::vector<std::string> names;
  if (at == std::string::npos) return names;
  const size_t end = text.find("\n#", at + heading.size());
  const std::string section =
      text.substr(at, end == std::string::npos ? std::string::npos : end - at);
  static const std::regex row("\\n\\| `([a-z_]+)` \\|");
  for (std::sregex_iterator it(section.begin(), section.end(), row), stop; it != stop; ++it) {
    names.push_back((*it)[1]);
  }
  return names;
}

// Fails unless `message` is not empty and contains each of `parts`.
inline void ExpectMentions(const std::string& message, const std::vector<std::string>& parts) {
  ASSERT_FALSE(message.empty()) << "the file was accepted";
  for (const auto& p : parts) {
    EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' not in: " << message;
  }
}

}  // namespace colony::testing
