// The tutorial's user effect (examples/user-effect, docs/tutorial-effect.md) is built as a real
// plugin and loaded the way `ricochet --plugin` loads it, so the tutorial cannot rot.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace ricochet
