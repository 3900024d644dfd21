// Data-driven tests: one file per effect in tests/engine/effects/<name>.toml, run by this one
// program (the LAMMPS force-style test pattern). Every registered effect must have a test file
// and a documentation page docs/effects/<name>.md.
//
// [[case]] entries hold regression references (V_out); RICOCHET_REGENERATE=1 rewrites them.
// [[trend]] entries are physics (e.g. "more en2, higher rebound") and are never regenerated.
#include <gtest/gtest.h>

#include <toml++/toml.h>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "effects/model.hpp"
#include "effects/registry.hpp"
#include "engine/engine.hpp"

namespace ricochet {
namespace {

namespace fs = std::filesystem;
const fs::path kSource(RICOCHET_SOURCE_DIR);

struct CaseSetup {
  Model model;
  Shape shape;
  CollisionCase c;
};

CaseSetup setup(const toml::table& file, const toml::table& entry) {
  const std::string effect = *file["effect"].value<std::string>();
  Model model = Model::paper();
  if (!model.has_effect(effect)) model = model.with_effect(effect);
  const std::string shape =
      entry["shape"].value_or(file["shape"].value_or(std::string("cylinder")));
  CollisionCase c;
  const toml::array& vin = *entry["vin"].as_array();
  for (std::size_t k = 0; k < 3; ++k) c.vin[k] = *vin.get(k)->value<double>();
  c.alpha_rad = entry["alpha_deg"].value_or(0.0) * M_PI / 180.0;
  if (const toml::table* set = entry["set"].as_table())
    for (const auto& [k, v] : *set) model.set(k.str(), *v.value<double>());
  return {model, Shape::resolve(shape), c};
}

double output_of(const CollisionResult& r, const std::string& name) {
  if (name == "vx") return r.vout[kVx];
  if (name == "vy") return r.vout[kVy];
  if (name == "w") return r.vout[kW];
  if (name == "contact_duration") return r.contact_duration_s;
  if (name == "max_penetration") return r.max_penetration_m;
  throw std::invalid_argument("unknown output " + name);
}

class EffectCases : public ::testing::TestWithParam<std::string> {};

TEST_P(EffectCases, ReferencesAndTrends) {
  const fs::path path = kSource / "tests/engine/effects" / (GetParam() + ".toml");
  ASSERT_TRUE(fs::exists(path)) << "every registered effect needs a test file: " << path;
  ASSERT_TRUE(fs::exists(kSource / "docs/effects" / (GetParam() + ".md")))
      << "every registered effect needs a doc page docs/effects/" << GetParam() << ".md";
  const toml::table file = toml::parse_file(path.string());
  ASSERT_EQ(file["effect"].value_or(std::string()), GetParam());

  const bool regenerate = std::getenv("RICOCHET_REGENERATE") != nullptr;
  std::vector<std::string> fresh;
  const toml::array* cases = file["case"].as_array();
  ASSERT_TRUE(cases && !cases->empty()) << path;
  for (const auto& node : *cases) {
    const toml::table& entry = *node.as_table();
    const CaseSetup run = setup(file, entry);
    const auto r = simulate(run.model, run.shape, run.c);
    EXPECT_EQ(r.status, CollisionStatus::kOk) << path;
    std::ostringstream s;
    s.precision(10);
    s << "vout = [" << r.vout[0] << ", " << r.vout[1] << ", " << r.vout[2] << "]";
    fresh.push_back(s.str());
    const toml::array* ref = entry["vout"].as_array();
    if (regenerate) continue;
    ASSERT_TRUE(ref && ref->size() == 3)
        << path << ": no reference; run with RICOCHET_REGENERATE=1";
    for (std::size_t k = 0; k < 3; ++k) {
      const double want = *ref->get(k)->value<double>();
      EXPECT_NEAR(r.vout[k], want, 1e-6 * (1.0 + std::fabs(want))) << path << " component " << k;
    }
  }
  if (regenerate) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    std::string out, line;
    std::size_t next = 0;
    std::istringstream lines(text.str());
    while (std::getline(lines, line)) {
      if (line.rfind("vout = [", 0) == 0 && next < fresh.size()) line = fresh[next++];
      out += line + "\n";
    }
    std::ofstream(path) << out;
  }

  if (const toml::array* trends = file["trend"].as_array()) {
    for (const auto& node : *trends) {
      const toml::table& entry = *node.as_table();
      CaseSetup run = setup(file, entry);
      const std::string param = *entry["parameter"].value<std::string>();
      const std::string output = *entry["output"].value<std::string>();
      const bool increasing = *entry["direction"].value<std::string>() == "increasing";
      double previous = NAN;
      for (const auto& v : *entry["values"].as_array()) {
        run.model.set(param, *v.value<double>());
        const double y = output_of(simulate(run.model, run.shape, run.c), output);
        if (!std::isnan(previous)) {
          if (increasing)
            EXPECT_GT(y, previous) << path << ": " << output << " vs " << param;
          else
            EXPECT_LT(y, previous) << path << ": " << output << " vs " << param;
        }
        previous = y;
      }
    }
  }
}

// The hand-written effects; the generated coefficient laws share one doc page and are tested in
// coefficient_law_test.cpp.
std::vector<std::string> hand_written() {
  std::vector<std::string> out;
  const EffectRegistry r = EffectRegistry::with_builtins();
  for (const auto& n : r.names())
    if (!r.get(n).signature().generated) out.push_back(n);
  return out;
}

INSTANTIATE_TEST_SUITE_P(Registry, EffectCases, ::testing::ValuesIn(hand_written()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace ricochet
