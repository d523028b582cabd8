// ARGoS compatibility layer (Colony): CARGoSException and the macros that
// throw it. A controller's Init that throws one stops the run with the
// message; when the error is about a parameter of the experiment file (a
// missing or malformed attribute), Colony names the file, line and attribute.
#pragma once

#include <exception>
#include <sstream>
#include <string>

namespace argos {

class CARGoSException : public std::exception {
 public:
  // `nested`, the exception being wrapped (THROW_ARGOSEXCEPTION_NESTED): its
  // message is appended after "[NESTED]", as in ARGoS.
  explicit CARGoSException(const std::string& what, const std::exception* nested = nullptr)
      : what_(what) {
    if (nested == nullptr) return;
    what_ += "\n[NESTED] ";
    what_ += nested->what();
    if (const auto* inner = dynamic_cast<const CARGoSException*>(nested)) {
      parameter_ = inner->parameter_;
      value_ = inner->value_;
    }
  }
  const char* what() const noexcept override { return what_.c_str(); }

  // Colony: the experiment-file parameter this error is about (a dotted path
  // such as "wheel_turning.max_speed"), empty when none; kept through
  // nesting.
  const std::string& parameter() const { return parameter_; }
  const std::string& value() const { return value_; }
  void SetParameter(std::string parameter, std::string value) {
    parameter_ = std::move(parameter);
    value_ = std::move(value);
  }

 private:
  std::string what_;
  std::string parameter_;
  std::string value_;
};

}  // namespace argos

#define THROW_ARGOSEXCEPTION(message)                  \
  {                                                    \
    std::ostringstream argos_what_;                    \
    argos_what_ << message;                            \
    throw ::argos::CARGoSException(argos_what_.str()); \
  }
#define THROW_ARGOSEXCEPTION_NESTED(message, nested)              \
  {                                                               \
    std::ostringstream argos_what_;                               \
    argos_what_ << message;                                       \
    throw ::argos::CARGoSException(argos_what_.str(), &(nested)); \
  }
#ifndef NDEBUG
#define ARGOS_ASSERT(condition, message)             \
  {                                                  \
    if (!(condition)) THROW_ARGOSEXCEPTION(message); \
  }
#else
#define ARGOS_ASSERT(condition, message)
#endif
