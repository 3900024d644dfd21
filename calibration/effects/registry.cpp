#include "effects/registry.hpp"

#include <dlfcn.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "effects/coefficient_law.hpp"
#include "effects/force_term.hpp"

namespace ricochet {
namespace effects {
// The factories of the built-in effects, one per file (builtin_effects.def).
#define RICOCHET_EFFECT(file) std::unique_ptr<Effect> make_##file();
#define RICOCHET_EFFECT_FAMILY(file, factory) std::vector<std::unique_ptr<Effect>> factory();
#include "effects/builtin_effects.def"
#undef RICOCHET_EFFECT
#undef RICOCHET_EFFECT_FAMILY
}  // namespace effects

namespace {

[[noreturn]] void refuse(const std::string& effect, const std::string& why) {
  throw std::invalid_argument("effect '" + effect + "': " + why);
}

// An enum value outside its table: a plugin built against a newer header, or a cast.
template <class E>
void check_enum(const std::string& effect, E value, std::size_t count, const char* what) {
  if (static_cast<std::size_t>(value) >= count)
    refuse(effect, std::string("declares ") + what + " " +
                       std::to_string(static_cast<long long>(value)) + ", which is unknown");
}

void check_parameters(const std::string& name, std::span<const ParameterSpec> params) {
  for (std::size_t i = 0; i < params.size(); ++i) {
    const auto& p = params[i];
    const std::string pn(p.name);
    for (std::size_t j = 0; j < i; ++j)
      if (params[j].name == p.name) refuse(name, "declares parameter '" + pn + "' twice");
    if (!(p.lower <= p.nominal && p.nominal <= p.upper))
      refuse(name, "nominal value of '" + pn + "' lies outside its bounds");
    if (!std::isnan(p.neutral) && !(p.lower <= p.neutral && p.neutral <= p.upper))
      refuse(name, "neutral value of '" + pn + "' lies outside its bounds");
    check_enum(name, p.role, kParameterRoleCount, ("the role of '" + pn + "'").c_str());
    check_enum(name, p.identified_by, kIdentifiedByCount, ("what identifies '" + pn + "'").c_str());
  }
}

// The engine's fused kernel reads a fused law's two parameters by role and its force from its
// first state variable (FusedLaw).
void check_fused_law(const std::string& name, const Effect& effect) {
  const FusedLaw law = effect.fused_law();
  check_enum(name, law, kFusedLawCount, "fused law");
  if (law == FusedLaw::kNone) return;
  for (ParameterRole role : fused_law_roles(law)) {
    std::size_t n = 0;
    for (const auto& p : effect.parameters()) n += p.role == role ? 1 : 0;
    if (n != 1)
      refuse(name, "its fused law needs exactly one parameter of role " +
                       std::string(role_name(role)) + ", not " + std::to_string(n));
  }
  if (effect.state().empty()) refuse(name, "its fused law keeps its force in a state variable");
}

}  // namespace

EffectRegistry EffectRegistry::with_builtins() {
  EffectRegistry r;
#define RICOCHET_EFFECT(file) r.add(effects::make_##file());
#define RICOCHET_EFFECT_FAMILY(file, factory) \
  for (auto& e : effects::factory()) r.add(std::move(e));
#include "effects/builtin_effects.def"
#undef RICOCHET_EFFECT
#undef RICOCHET_EFFECT_FAMILY
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
  check_enum(name, effect->stage(), kStageCount, "stage");
  const LawKind kind = effect->kind();
  check_enum(name, kind.family, kFamilyCount, "family");
  check_enum(name, kind.variable, kVariableCount, "variable");
  check_parameters(name, effect->parameters());
  check_fused_law(name, *effect);
  // The signature in the vocabulary's words: a misspelt word would otherwise make a trend
  // that the diagnosis never finds.
  for (const SignatureTrend& t : effect->signature().trends) {
    try {
      (void)parse_trend(t);
    } catch (const std::invalid_argument& e) {
      refuse(name, std::string("signature: ") + e.what());
    }
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
    if (e->generated()) {
      generated = true;
      continue;
    }
    known += (known.empty() ? "" : ", ") + std::string(e->name());
  }
  throw std::invalid_argument("unknown effect '" + std::string(name) +
                              "'; known effects: " + known +
                              (generated ? "; and the " + effects::coefficient_law_family_text() +
                                               "; and the " + effects::force_term_family_text()
                                         : std::string()));
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
  try {
    fn(*this);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(path + ": plugin refused: " + e.what());
  }
}

}  // namespace ricochet
