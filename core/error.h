// Errors. User input (experiment files, command lines) produces ConfigError,
// carrying every problem found in one read, each naming the file, line,
// element, attribute, the bad value and what is accepted. The command line
// program turns it into exit status 2.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace colony {

struct Diagnostic {
  std::string file;
  int line = 0;
  std::string element;    // without brackets; empty when not about an element
  std::string attribute;  // empty when about the element itself
  std::string value;      // the offending value, if any
  std::string message;    // what is wrong, and what is accepted
  std::string ToString() const;
};

class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(std::vector<Diagnostic> diagnostics);
  explicit ConfigError(const std::string& message);  // one problem with no location
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

 private:
  std::vector<Diagnostic> diagnostics_;
};

// Collects problems during one read so they are reported together.
class Diagnostics {
 public:
  void Add(Diagnostic d) { items_.push_back(std::move(d)); }
  bool empty() const { return items_.empty(); }
  size_t size() const { return items_.size(); }
  // Throws ConfigError with everything collected so far, if anything.
  void ThrowIfAny();

 private:
  std::vector<Diagnostic> items_;
};

// A failure while running (exit status 1).
class RuntimeFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The closest of `candidates` to `word` if it is close enough to be a typo.
std::string DidYouMean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace colony
