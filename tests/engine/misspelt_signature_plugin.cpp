// A plugin whose signature uses a word outside the vocabulary ("speed" for the feature
// "speed_in"): the registry must refuse it when the plugin registers it (plugin_test.cpp), or
// the diagnosis would look for a trend it never computes and silently cite nothing.
#include <memory>

#include "effects/effect.hpp"
#include "effects/registry.hpp"

namespace {

constexpr ricochet::ParameterSpec kParams[] = {
    {"k_misspelt", "-", 0.0, 1.0, 0.0, 0.0, true, "a gain that does nothing"},
};
constexpr ricochet::SignatureTrend kTrends[] = {
    {"residual vy", "abs_vin_y"},
    {"residual vy", "speed"},
};

class MisspeltSignature final : public ricochet::Effect {
 public:
  std::string_view name() const override { return "misspelt_signature"; }
  std::string_view summary() const override { return "a test plugin with a misspelt signature"; }
  std::string_view equation() const override { return "nothing"; }
  std::string_view reference() const override { return "tests/engine/plugin_test.cpp"; }
  ricochet::Stage stage() const override { return ricochet::Stage::kCoefficient; }
  ricochet::LawKind kind() const override {
    return {ricochet::Family::kRestitution, ricochet::Variable::kImpactSpeed};
  }
  ricochet::Signature signature() const override { return {"a misspelt signature", kTrends}; }
  std::span<const ricochet::ParameterSpec> parameters() const override { return kParams; }
  void apply(const ricochet::ContactBatch&, const double* const*, double* const*) const override {}
};

}  // namespace

extern "C" void ricochet_register_effects(ricochet::EffectRegistry& registry) {
  registry.add(std::make_unique<MisspeltSignature>());
}
