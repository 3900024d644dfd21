// Errors that tell the user where their input is wrong.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace ricochet {

/// An error in a user's input (data file, model file, command-line value).
/// It names the file, the 1-based line (0 when not applicable) and the field (a column name,
/// a TOML key, a command-line option), so the message points at the exact cell to fix.
/// what() reads "FILE:LINE: field 'FIELD': MESSAGE".
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, std::size_t line, std::string field, const std::string& message);

  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }
  const std::string& field() const { return field_; }
  /// The message without the location prefix.
  const std::string& detail() const { return detail_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string field_;
  std::string detail_;
};

}  // namespace ricochet
