// The explicit registry of effects: name -> Effect. Built-ins are listed in one table,
// effects/builtin_effects.def; users add their own with add() in their program, or with
// load_plugin() from the command line (`ricochet ... --plugin libmyeffect.so`), without touching
// the engine (docs/tutorial-effect.md). Every effect's declaration is checked when it is stored,
// built-ins and plugins alike.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "effects/effect.hpp"

namespace ricochet {

class EffectRegistry {
 public:
  /// A registry holding the built-in effects only.
  static EffectRegistry with_builtins();
  /// The process-wide registry used by the command-line tools (built-ins plus plugins).
  static EffectRegistry& global();

  /// Adds an effect. Throws std::invalid_argument "effect 'X': ..." if its name is taken or
  /// empty, if a parameter name is declared twice, if a nominal or neutral value lies outside
  /// its bounds, if a declared enum value (stage, family, variable, role, what identifies a
  /// parameter, fused law) is unknown, if a fused law lacks its parameter roles or its state, or
  /// if a signature trend uses a word outside the signature vocabulary (the message names the
  /// word and lists the known ones; effect.hpp, parse_trend).
  void add(std::unique_ptr<Effect> effect);
  /// Adds an effect owned by the caller, who keeps it alive as long as this registry and the
  /// models built from it (used by check_effect_invariants()).
  void add_borrowed(const Effect& effect);
  /// Throws std::invalid_argument "unknown effect 'X'; known effects: a, b, ..." for an unknown
  /// name.
  const Effect& get(std::string_view name) const;
  bool contains(std::string_view name) const;
  std::vector<std::string> names() const;
  std::vector<const Effect*> all() const;

  /// Loads a shared library that defines
  ///   extern "C" void ricochet_register_effects(ricochet::EffectRegistry&);
  /// and calls it. Throws std::runtime_error naming the file on failure, including an effect
  /// that add() refuses ("PATH: plugin refused: effect 'X': ...").
  void load_plugin(const std::string& path);

 private:
  void check_and_store(std::shared_ptr<const Effect> effect);
  std::vector<std::shared_ptr<const Effect>> effects_;
};

/// Signature of the plugin entry point.
using RegisterEffectsFn = void (*)(EffectRegistry&);
inline constexpr const char* kPluginEntryPoint = "ricochet_register_effects";

}  // namespace ricochet
