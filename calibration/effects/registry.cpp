#include "effects/registry.hpp"

#include <dlfcn.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "effects/builtin.hpp"
#include "effects/coefficient_law.hpp"

namespace ricochet {

std::string_view family_name(Family family) {
  static constexpr std::array<std::string_view, kFamilyCount> kNames = {
      "none",      "restitution", "sliding_friction", "rolling_resistance",
      "stiffness", "drag",        "ploughing",        "other"};
  return kNames[static_cast<std::size_t>(family)];
}

std::string_view variable_name(Variable variable) {
  static constexpr std::array<std::string_view, kVariableCount> kNames = {
      "none", "impact_speed", "normal_speed",    "penetration",
      "spin", "slip_speed",   "incidence_angle", "other"};
  return kNames[static_cast<std::size_t>(variable)];
}

std::string_view stage_name(Stage stage) {
  switch (stage) {
    case Stage::kCoefficient:
      return "coefficient";
    case Stage::kNormal:
      return "normal";
    case Stage::kTangential:
      return "tangential";
    case Stage::kRolling:
      return "rolling";
    case Stage::kBody:
      return "body";
  }
  return "?";
}

std::string Effect::law(std::span<const double> values) const {
  std::string out(equation());
  const auto specs = parameters();
  for (std::size_t i = 0; i < specs.size() && i < values.size(); ++i) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.4g", values[i]);
    out += (i == 0 ? ", " : ", ") + std::string(specs[i].name) + " = " + buf;
    if (specs[i].unit != "-") out += " " + std::string(specs[i].unit);
  }
  return out;
}

EffectRegistry EffectRegistry::with_builtins() {
  EffectRegistry r;
  // The paper's law, then the catalog of candidate missing physics, one per family.
  r.add(effects::make_normal());
  r.add(effects::make_tangential());
  r.add(effects::make_rolling());
  r.add(effects::make_rate_restitution());
  r.add(effects::make_inertial_drag());
  r.add(effects::make_ploughing());
  r.add(effects::make_depth_friction());
  r.add(effects::make_hertz_stiffness());
  // The generated family: every coefficient as a linear or power function of a variable.
  for (auto& law : effects::make_coefficient_laws()) r.add(std::move(law));
  return r;
}

EffectRegistry& EffectRegistry::global() {
  static EffectRegistry registry = with_builtins();
  return registry;
}

void EffectRegistry::add(std::unique_ptr<Effect> effect) {
  check_and_store(std::shared_ptr<const Effect>(std::move(effect)));
}

void EffectRegistry::add_borrowed(const Effect& effect) {
  check_and_store(std::shared_ptr<const Effect>(&effect, [](const Effect*) {}));
}

void EffectRegistry::check_and_store(std::shared_ptr<const Effect> effect) {
  const std::string name(effect->name());
  if (name.empty()) throw std::invalid_argument("an effect must have a name");
  if (contains(name)) throw std::invalid_argument("effect '" + name + "' is already registered");
  const auto params = effect->parameters();
  for (std::size_t i = 0; i < params.size(); ++i) {
    const auto& p = params[i];
    for (std::size_t j = 0; j < i; ++j)
      if (params[j].name == p.name)
        throw std::invalid_argument("effect '" + name + "' declares parameter '" +
                                    std::string(p.name) + "' twice");
    if (!(p.lower <= p.nominal && p.nominal <= p.upper))
      throw std::invalid_argument("effect '" + name + "': nominal value of '" +
                                  std::string(p.name) + "' lies outside its bounds");
    if (!std::isnan(p.neutral) && !(p.lower <= p.neutral && p.neutral <= p.upper))
      throw std::invalid_argument("effect '" + name + "': neutral value of '" +
                                  std::string(p.name) + "' lies outside its bounds");
  }
  effects_.push_back(std::move(effect));
}

const Effect& EffectRegistry::get(std::string_view name) const {
  for (const auto& e : effects_)
    if (e->name() == name) return *e;
  // The generated family is described by its pattern rather than 40 names.
  std::string known;
  bool generated = false;
  for (const auto& e : effects_) {
    if (e->signature().generated) {
      generated = true;
      continue;
    }
    known += (known.empty() ? "" : ", ") + std::string(e->name());
  }
  throw std::invalid_argument(
      "unknown effect '" + std::string(name) + "'; known effects: " + known +
      (generated ? "; and the " + effects::coefficient_law_family_text() : std::string()));
}

bool EffectRegistry::contains(std::string_view name) const {
  for (const auto& e : effects_)
    if (e->name() == name) return true;
  return false;
}

std::vector<std::string> EffectRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& e : effects_) out.emplace_back(e->name());
  return out;
}

std::vector<const Effect*> EffectRegistry::all() const {
  std::vector<const Effect*> out;
  for (const auto& e : effects_) out.push_back(e.get());
  return out;
}

void EffectRegistry::load_plugin(const std::string& path) {
  // RTLD_NODELETE: the effects' code must stay mapped as long as the registry lives.
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
  if (!handle) throw std::runtime_error(path + ": cannot load plugin: " + dlerror());
  auto fn = reinterpret_cast<RegisterEffectsFn>(dlsym(handle, kPluginEntryPoint));
  if (!fn)
    throw std::runtime_error(path + ": plugin has no entry point " +
                             std::string(kPluginEntryPoint));
  fn(*this);
}

}  // namespace ricochet
