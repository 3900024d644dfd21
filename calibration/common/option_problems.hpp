// What is wrong with a set of options. Each library options struct has one `problems()` (the
// model is Ceres's Solver::Options::IsValid): the list of its problems, empty when the options
// are valid, each naming the field at fault and its allowed range. The function that consumes
// the options calls require_valid() at its entry, so a program calling the library gets the same
// refusal as the command line; the command line calls problems() before any work, and prints the
// library's message under its own option name (cli/cli_common.hpp, refuse_problems). The range
// of an option is thus written once, in the library, next to its default.
#pragma once

#include <string>
#include <vector>

namespace ricochet {

/// One problem of a set of options.
struct OptionProblem {
  /// The field at fault as the options struct spells it; a nested struct's field is prefixed by
  /// the member's name and a dot ("fit.starts", "assess.repeats").
  std::string option;
  std::string message;  ///< what is wrong and what is allowed: "value 0 is outside [1, 20]"
};
using OptionProblems = std::vector<OptionProblem>;

/// An interval an option's value must lie in; closed at a bound unless that bound is open.
struct OptionRange {
  double lo = 0, hi = 0;
  bool lo_open = false, hi_open = false;
  bool contains(double value) const;  ///< false for NaN
  std::string text() const;           ///< "[1, 20]", "(0, 1)" (bounds printed with %g)
};

/// Appends {option, "value V is outside RANGE"} to `problems` when `value` is outside `range`.
void check_range(OptionProblems& problems, const std::string& option, double value,
                 const OptionRange& range);

/// Appends `nested`'s problems to `problems`, each option name prefixed by "member.".
void append_nested(OptionProblems& problems, const std::string& member,
                   const OptionProblems& nested);

/// Throws InputError (file "<options of CONSUMER>", field: the option, message: the problem's)
/// for the first of `problems`; returns when there is none. `consumer` names the function whose
/// options these are ("diagnosis::assess").
void require_valid(const OptionProblems& problems, const std::string& consumer);

}  // namespace ricochet
