#include "common/error.hpp"

namespace ricochet {
namespace {
std::string format_location(const std::string& file, std::size_t line, const std::string& field,
                            const std::string& message) {
  // Appends to one string: GCC 12 reports a spurious -Wrestrict on chained operator+ here.
  std::string out;
  out.reserve(file.size() + field.size() + message.size() + 32);
  out.append(file.empty() ? "<input>" : file);
  if (line > 0) out.append(":").append(std::to_string(line));
  out.append(": ");
  if (!field.empty()) out.append("field '").append(field).append("': ");
  out.append(message);
  return out;
}
}  // namespace

InputError::InputError(std::string file, std::size_t line, std::string field,
                       const std::string& message)
    : std::runtime_error(format_location(file, line, field, message)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)),
      detail_(message) {}

}  // namespace ricochet
