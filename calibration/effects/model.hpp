// A contact model: an ordered composition of effects with parameter values.
//
// The paper's law is Model::paper() = normal + tangential + rolling. Adding physics is adding an
// effect: in a model file one more name in `effects`, on the command line one --add.
//
// Model file (TOML), e.g. docs/examples/paper-plus-drag.toml:
//   effects = ["normal", "tangential", "rolling", "inertial_drag"]
//   calibrate = ["en2", "mu", "muR", "cd"]   # optional; default: parameters flagged calibrated
//   hold = ["kn"]                             # optional; never fitted, not even where the
//                                             #   contact features would identify them
//   [parameters]                              # optional; default: nominal values
//   en2 = 0.15
//   cd = 50.0                                 # kg/m
//   [bounds]                                  # optional narrower calibration bounds
//   mu = [0.0, 1.0]
//   [[law]]                                   # optional generated coefficient laws
//   coefficient = "muR"                       #   (effects/coefficient_law.hpp); the same as
//   variable = "spin"                         #   naming "muR_spin_linear" in `effects`; one
//   form = "linear"                           #   [[law]] table per law
// A [[law]] error (unknown coefficient, variable or form, missing or unknown key, a law named
// twice) is an InputError naming the file, the line and the key (law.variable, ...) and listing
// the accepted values. to_toml() writes generated laws back as [[law]] tables, with the law and
// its numbers in a comment; a law that must precede a hand-written coefficient effect to keep
// the model's order keeps its name in `effects` instead (the round trip is exact either way).
#pragma once

#include <cstddef>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "effects/effect.hpp"
#include "effects/registry.hpp"

namespace ricochet {

class Model {
 public:
  Model() = default;

  /// The paper's law (Garcia et al. 2020, Eq. 3, 5, 6) at nominal values.
  static Model paper(const EffectRegistry& registry = EffectRegistry::global());
  /// Composition of the named effects. Effects act in stage order (coefficient, normal,
  /// tangential, rolling, body), keeping the given order within a stage. Throws
  /// std::invalid_argument for an unknown name (listing the known ones), a repeated effect, a
  /// parameter name declared by two effects, or a model without a normal-force effect.
  static Model from_names(const std::vector<std::string>& names,
                          const EffectRegistry& registry = EffectRegistry::global());
  /// Reads a model file. Throws InputError naming file, line and key.
  static Model from_toml_file(const std::string& path,
                              const EffectRegistry& registry = EffectRegistry::global());
  static Model from_toml_string(const std::string& text, const std::string& name,
                                const EffectRegistry& registry = EffectRegistry::global());

  /// A copy with one more effect at its nominal values (or its neutral values when
  /// `at_neutral`, so that the new model starts exactly where this one is).
  Model with_effect(std::string_view name, bool at_neutral = false,
                    const EffectRegistry& registry = EffectRegistry::global()) const;

  const std::vector<const Effect*>& effects() const { return effects_; }
  std::vector<std::string> effect_names() const;
  bool has_effect(std::string_view name) const;

  /// Parameters, concatenated over effects in effects() order.
  std::size_t parameter_count() const { return specs_.size(); }
  const ParameterSpec& spec(std::size_t i) const { return specs_[i]; }
  /// Index of the first parameter of effect e in the parameter vector.
  std::size_t offset(std::size_t effect_index) const { return offsets_[effect_index]; }
  /// Throws std::invalid_argument listing the model's parameter names for an unknown name.
  std::size_t index(std::string_view name) const;
  std::vector<std::string> parameter_names() const;

  const std::vector<double>& values() const { return values_; }
  double value(std::string_view name) const { return values_[index(name)]; }
  /// Sets a value; throws std::out_of_range "NAME = V is outside [LO, HI] UNIT" when out of bounds.
  void set(std::string_view name, double value);
  /// Sets all values (size must match); bounds checked.
  void set_values(const std::vector<double>& values);
  /// Parses "NAME=VALUE" (the --set syntax); throws InputError (field = option) when malformed.
  void set_from_string(const std::string& assignment, const std::string& option = "--set");

  /// Calibration bounds (the declared bounds, possibly narrowed by the model file).
  double lower(std::size_t i) const { return lower_[i]; }
  double upper(std::size_t i) const { return upper_[i]; }
  void set_bounds(std::string_view name, double lower, double upper);
  /// Whether calibration fits parameter i (default: ParameterSpec::calibrated).
  bool calibrated(std::size_t i) const { return calibrated_[i]; }
  void set_calibrated(std::string_view name, bool on);
  std::vector<std::size_t> calibrated_indices() const;
  /// Whether parameter i is held: no calibration fits it, not even where the set's contact
  /// features would identify it (fit::calibration_model). A held law predicts with its values
  /// as given. Holding a parameter also clears its calibrated flag; a held parameter cannot be
  /// flagged calibrated (std::invalid_argument naming it).
  bool held(std::size_t i) const { return held_[i]; }
  void set_held(std::string_view name, bool on);

  /// Checks `values` against the declared bounds; throws std::out_of_range naming the parameter.
  void check(const std::vector<double>& values) const;

  nlohmann::json to_json() const;
  std::string to_toml() const;

 private:
  void add(const Effect& effect);
  void finish();
  /// The names of the parameters whose flag is set, in parameter order.
  std::vector<std::string> names_of(const std::vector<bool>& flags) const;

  std::vector<const Effect*> effects_;
  std::vector<std::size_t> offsets_;
  std::vector<ParameterSpec> specs_;
  std::vector<double> values_, lower_, upper_;
  std::vector<bool> calibrated_, held_;
};

}  // namespace ricochet
