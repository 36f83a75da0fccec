// isoatlas::Error: what library code throws. The message says what was wrong and where (file,
// byte/line, value) so a user can act on it; the CLI prints it as one line and exits 2 for bad
// input, 1 when the work itself failed.
#pragma once
#include <stdexcept>
#include <string>

namespace isoatlas {

enum class ErrorKind { BadInput, Failure };

class Error : public std::runtime_error {
public:
  explicit Error(std::string message, ErrorKind kind = ErrorKind::BadInput)
      : std::runtime_error(std::move(message)), kind_(kind) {}
  ErrorKind kind() const { return kind_; }
  int exitCode() const { return kind_ == ErrorKind::BadInput ? 2 : 1; }

private:
  ErrorKind kind_;
};

// Throws Error(BadInput) with `message` unless `ok`.
inline void require(bool ok, const std::string& message) {
  if (!ok) throw Error(message);
}

}  // namespace isoatlas
