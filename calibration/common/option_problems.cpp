#include "common/option_problems.hpp"

#include <fmt/format.h>

#include "common/error.hpp"

namespace ricochet {

bool OptionRange::contains(double value) const {
  const bool above = lo_open ? value > lo : value >= lo;
  const bool below = hi_open ? value < hi : value <= hi;
  return above && below;  // NaN compares false: outside every range
}

std::string OptionRange::text() const {
  return fmt::format("{}{:g}, {:g}{}", lo_open ? '(' : '[', lo, hi, hi_open ? ')' : ']');
}

void check_range(OptionProblems& problems, const std::string& option, double value,
                 const OptionRange& range) {
  if (!range.contains(value))
    problems.push_back({option, fmt::format("value {} is outside {}", value, range.text())});
}

void append_nested(OptionProblems& problems, const std::string& member,
                   const OptionProblems& nested) {
  for (const OptionProblem& p : nested) problems.push_back({member + "." + p.option, p.message});
}

void require_valid(const OptionProblems& problems, const std::string& consumer) {
  if (problems.empty()) return;
  throw InputError("<options of " + consumer + ">", 0, problems.front().option,
                   problems.front().message);
}

}  // namespace ricochet
