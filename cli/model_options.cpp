#include "model_options.hpp"

#include "cli_common.hpp"
#include "common/error.hpp"

namespace ricochet::cli {

void add_model_options(CLI::App* sub, ModelOptions& o, bool with_shape) {
  sub->add_option("--model", o.model_file, "Model file (TOML); default: the paper's law");
  sub->add_option("--add", o.add, "Add an effect to the model (repeatable)");
  sub->add_option("--set", o.set, "Set a model parameter, NAME=VALUE (repeatable)");
  sub->add_option("--hold", o.hold,
                  "Keep a parameter at its model value in every fit, even where the data's contact "
                  "features would calibrate it (kn, w_rim): a held law (repeatable)");
  sub->add_option("--plugin", o.plugins, "Load user effects from a shared library (repeatable)");
  if (with_shape)
    sub->add_option("--shape", o.shape, "cylinder, triangle, or a shape file (.toml)")
        ->capture_default_str();
  sub->add_option("--dt", o.dt_s, "Time step [s]")->capture_default_str();
  show_range(sub, "--dt", EngineOptions::kDt);
}

Model ModelOptions::build_model() const {
  auto& registry = EffectRegistry::global();
  for (const auto& p : plugins) {
    try {
      registry.load_plugin(p);
    } catch (const std::exception& e) {
      throw InputError(p, 0, "--plugin", e.what());
    }
  }
  Model model;
  if (!model_file.empty()) {
    model = Model::from_toml_file(model_file, registry);
  } else {
    model = Model::paper(registry);
  }
  for (const auto& name : add) {
    try {
      model = model.with_effect(name, false, registry);
    } catch (const std::exception& e) {
      throw InputError("<command line>", 0, "--add", e.what());
    }
  }
  for (const auto& s : set) model.set_from_string(s, "--set");
  for (const auto& name : hold) {
    try {
      model.set_held(name, true);
    } catch (const std::exception& e) {
      throw InputError("<command line>", 0, "--hold", e.what());
    }
  }
  return model;
}

EngineOptions ModelOptions::engine_options() const {
  EngineOptions o;
  o.dt_s = dt_s;
  refuse_problems(o.problems(), {{"dt_s", "--dt"}});
  return o;
}

}  // namespace ricochet::cli
