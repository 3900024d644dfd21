// The one check of each diagnosis options struct (problems()), and the one parse and the one
// resolution of the number of folds (assess.hpp, diagnose.hpp, validation_report.hpp).
#include <algorithm>
#include <charconv>

#include "common/error.hpp"
#include "diagnosis/diagnose.hpp"
#include "diagnosis/validation_report.hpp"

namespace ricochet::diagnosis {

std::size_t AssessOptions::folds_for(std::size_t n) const {
  return std::clamp<std::size_t>(folds, 2, std::max<std::size_t>(2, n));
}

std::size_t parse_folds(const std::string& text, const std::string& option) {
  if (text == "loro") return AssessOptions::kLeaveOneOut;
  std::size_t k = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), k);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size())
    throw InputError("<command line>", 0, option,
                     "'" + text + "': expected an integer >= 2 or 'loro'");
  return k;
}

OptionProblems AssessOptions::problems() const {
  OptionProblems p;
  if (folds < 2)
    p.push_back({"folds", "value " + std::to_string(folds) +
                              " is below 2: a held-out error needs two folds at least"});
  check_range(p, "repeats", static_cast<double>(repeats), kRepeats);
  const OptionRange& starts = fit::FitOptions::kStarts;
  check_range(p, "population_starts", population_starts, starts);
  check_range(p, "contact_population_starts", contact_population_starts, starts);
  check_range(p, "warm_starts", warm_starts, starts);
  check_range(p, "fold_starts", fold_starts, starts);
  check_range(p, "marginal_starts", marginal_starts, starts);
  check_range(p, "fold_warm_starts", fold_warm_starts, starts);
  check_range(p, "fold_warm_design_points", fold_warm_design_points,
              fit::FitOptions::kDesignPoints);
  check_range(p, "fold_refinements", static_cast<double>(fold_refinements), starts);
  append_nested(p, "fit", fit.problems());
  return p;
}

OptionProblems DiagnoseOptions::problems() const {
  OptionProblems p;
  check_range(p, "alpha", alpha, kAlpha);
  check_range(p, "screen", static_cast<double>(screen), kScreen);
  check_range(p, "score_draws", static_cast<double>(score_draws), kScoreDraws);
  check_range(p, "probe_fraction", probe_fraction, kProbeFraction);
  check_range(p, "adequate_z", adequate_z, kAdequateZ);
  append_nested(p, "assess", assess.problems());
  return p;
}

OptionProblems ReportOptions::problems() const {
  OptionProblems p;
  check_range(p, "rounds", rounds, kRounds);
  append_nested(p, "diagnose", diagnose.problems());
  return p;
}

}  // namespace ricochet::diagnosis
