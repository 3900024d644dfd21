// Options shared by `ricochet montecarlo` and `ricochet sobol`: which parameters vary and how.
//   --range NAME=LO:HI  uniform range of a parameter (repeatable; adds or overrides)
//   --fix NAME          keep a calibrated parameter at its model value (repeatable)
// Default inputs: every calibrated parameter of the model, uniform over the paper's range when
// it has one (en2 [0.05, 0.25], mu [0, 0.6], muR [0, 0.3]; section 4.3), else over its
// calibration bounds.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "effects/model.hpp"
#include "impact/impact_set.hpp"
#include "uq/distribution.hpp"

namespace ricochet::cli {

struct InputOptions {
  std::vector<std::string> ranges, fixed;
  /// The varied parameters with their distributions; throws InputError naming the option.
  std::vector<uq::ParameterInput> build(const Model& model) const;
};
void add_input_options(CLI::App* sub, InputOptions& options);

}  // namespace ricochet::cli
