// Small text and environment helpers shared by the core, the plugins and the
// programs (one home, so messages read the same everywhere).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace colony {

// A number as messages show it: the shortest of the default stream format
// ("0.5", "1e+09").
std::string FormatNumber(double v);
// "a, b, c" (or joined by `separator`).
std::string Join(const std::vector<std::string>& items, std::string_view separator = ", ");
// `text` without leading and trailing spaces and tabs.
std::string Trim(std::string_view text);
// Splits "a,b,c" into trimmed parts ("" gives one empty part).
std::vector<std::string> SplitList(std::string_view text, char separator = ',');
// Reads a command-line whole number in [min, max] into `value`. Returns ""
// or the message: "OPTION: 'TEXT' is not accepted; expected a whole number
// in [MIN, MAX]".
std::string ParseWholeOption(const std::string& option, const std::string& text, long long min,
                             long long max, long long& value);
// Whether an executable `program` is on the PATH.
bool OnPath(const std::string& program);

}  // namespace colony
