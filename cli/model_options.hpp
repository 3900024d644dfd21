// The model options shared by every command that runs the reduced engine:
//   --model FILE      model file (TOML, see effects/model.hpp); default: the paper's law
//   --add EFFECT      add an effect (repeatable), e.g. --add rate_restitution
//   --set NAME=VALUE  set a parameter (repeatable), bounds checked
//   --hold NAME       never calibrate a parameter, not even from the contact features (repeatable)
//   --plugin LIB      load user effects from a shared library (repeatable)
//   --shape S         cylinder | triangle | shape file (.toml)
//   --dt S            time step [s], in EngineOptions::kDt
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "effects/model.hpp"
#include "engine/engine.hpp"

namespace ricochet::cli {

struct ModelOptions {
  std::string model_file;
  std::vector<std::string> add, set, hold, plugins;
  std::string shape = "cylinder";
  double dt_s = EngineOptions{}.dt_s;

  /// Loads plugins, reads the model file, adds effects, applies --set and --hold. Errors name
  /// the option.
  Model build_model() const;
  Shape build_shape() const { return Shape::resolve(shape); }
  /// The engine's options with --dt; refuses (exit 2, refuse_problems) a --dt outside the
  /// engine's range, EngineOptions::kDt.
  EngineOptions engine_options() const;
};

/// Adds the options above to a subcommand. `with_shape` = false when the command takes the
/// shape from its data.
void add_model_options(CLI::App* sub, ModelOptions& options, bool with_shape = true);

}  // namespace ricochet::cli
