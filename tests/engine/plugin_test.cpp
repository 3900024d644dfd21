// The tutorial's user effect (examples/user-effect, docs/tutorial-effect.md) and the resolved
// campaigns' rebound threshold (examples/crater-escape) are built as real plugins and loaded the
// way `ricochet --plugin` loads them, so that neither can rot.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "effects/model.hpp"
#include "effects/registry.hpp"
#include "engine/effect_checks.hpp"
#include "engine/engine.hpp"

namespace ricochet {
namespace {

TEST(UserEffectPlugin, LoadsPassesTheInvariantsAndChangesTheRebound) {
  EffectRegistry registry = EffectRegistry::with_builtins();
  registry.load_plugin(RICOCHET_PLUGIN_PATH);
  ASSERT_TRUE(registry.contains("grazing_restitution"));
  const auto problems = check_effect_invariants(registry.get("grazing_restitution"));
  EXPECT_TRUE(problems.empty()) << problems.front();

  Model model = Model::paper(registry).with_effect("grazing_restitution", true, registry);
  const CollisionCase grazing{{2.9, -2.3, -65.0}, 0.0};
  const auto neutral = simulate(model, Shape::cylinder(), grazing);
  model.set("kg", 1.0);
  const auto boosted = simulate(model, Shape::cylinder(), grazing);
  EXPECT_GT(boosted.vout[kVy], neutral.vout[kVy] + 0.05);
}

TEST(UserEffectPlugin, MissingOrBrokenPluginIsAClearError) {
  EffectRegistry registry = EffectRegistry::with_builtins();
  try {
    registry.load_plugin("/nonexistent/libnothing.so");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/libnothing.so"), std::string::npos);
  }
}

TEST(UserEffectPlugin, WorksFromTheCommandLine) {
  const std::string cmd = std::string(RICOCHET_BIN) +
                          " simulate --vin 2.9,-2.3,-65 --json --plugin " + RICOCHET_PLUGIN_PATH +
                          " --add grazing_restitution --set kg=1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  ASSERT_TRUE(pipe);
  std::string out;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe.get())) out += buf;
  const auto j = nlohmann::json::parse(out);
  EXPECT_EQ(j["model"]["parameters"]["kg"], 1.0);
  EXPECT_GT(j["vout"][1].get<double>(), 0.9);
}

// A plugin is checked like a built-in when it registers: a signature word outside the
// vocabulary is refused, the error names the plugin, the effect, the word and the known words,
// and the effect is not registered. The command line says the same and exits with status 2.
TEST(PluginRegistration, AMisspeltSignatureWordIsRefused) {
  EffectRegistry registry = EffectRegistry::with_builtins();
  try {
    registry.load_plugin(RICOCHET_MISSPELT_PLUGIN_PATH);
    ADD_FAILURE() << "the plugin was accepted";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(RICOCHET_MISSPELT_PLUGIN_PATH), std::string::npos) << msg;
    EXPECT_NE(msg.find("effect 'misspelt_signature'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("unknown signature feature 'speed'"), std::string::npos) << msg;
    for (std::size_t i = 0; i < kImpactFeatureCount; ++i)
      EXPECT_NE(msg.find(std::string(feature_name(static_cast<ImpactFeature>(i)))),
                std::string::npos)
          << msg;
  }
  EXPECT_FALSE(registry.contains("misspelt_signature"));

  const std::string cmd =
      std::string(RICOCHET_BIN) + " effects --plugin " + RICOCHET_MISSPELT_PLUGIN_PATH + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  ASSERT_TRUE(pipe);
  std::string out;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe.get())) out += buf;
  const int status = pclose(pipe.release());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << status << "\n" << out;
  EXPECT_NE(out.find("unknown signature feature 'speed'; known features: speed_in"),
            std::string::npos)
      << out;
}

// crater_escape: e_n^2_eff = e_n^2 v0^2 / (v0^2 + vc2). Without gravity, a head-on impact without
// spin under the paper's law returns V_out^y = e_n |V_in^y| (Eq. 4: e_n^2 is the energy
// restitution of a closed cycle), so the ratio of the rebound with and without the threshold is
// sqrt(v0^2 / (v0^2 + vc2)): 1/sqrt(2) when vc2 = v0^2. And the restitution grows with the speed.
TEST(CraterEscapePlugin, HalvesTheReboundEnergyAtTheEscapeSpeedAndGrowsWithSpeed) {
  EffectRegistry registry = EffectRegistry::with_builtins();
  registry.load_plugin(RICOCHET_CRATER_PLUGIN_PATH);
  ASSERT_TRUE(registry.contains("crater_escape"));
  const auto problems = check_effect_invariants(registry.get("crater_escape"));
  EXPECT_TRUE(problems.empty()) << problems.front();

  Model model = Model::paper(registry).with_effect("crater_escape", true, registry);
  EngineOptions no_gravity;
  no_gravity.gravity_mps2 = 0.0;
  const auto rebound = [&](double vy, double vc2) {
    model.set("vc2", vc2);
    return simulate(model, Shape::cylinder(), {{0.0, vy, 0.0}, 0.0}, {}, no_gravity).vout[kVy] /
           -vy;
  };
  const double v = 2.3;  // m/s, the lab's mean vertical approach speed
  EXPECT_NEAR(rebound(-v, v * v) / rebound(-v, 0.0), 1.0 / std::sqrt(2.0), 0.02);
  // With the threshold the slow impact keeps less of its speed than the fast one; without it, the
  // paper's constant e_n^2 keeps the same fraction.
  const double vc2 = 1.0;  // m^2/s^2
  EXPECT_LT(rebound(-1.0, vc2), 0.8 * rebound(-4.0, vc2));
  EXPECT_NEAR(rebound(-1.0, 0.0), rebound(-4.0, 0.0), 0.02 * rebound(-4.0, 0.0));
}

}  // namespace
}  // namespace ricochet
