// Data-driven tests: one file per effect in tests/engine/effects/<name>.toml, run by this one
// program (the LAMMPS force-style test pattern). Every registered effect must have a test file
// and a documentation page docs/effects/<name>.md. The generated coefficient laws
// (Effect::generated()) share one page, docs/effects/coefficient_law.md, and one file,
// tests/engine/effects/coefficient_law.toml, whose entries each name their effect: every
// generated law needs a case there.
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
#include <set>
#include <sstream>

#include "effects/coefficient_law.hpp"
#include "effects/force_term.hpp"
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

// The entry's own `effect` (the generated family's file) or the file's.
CaseSetup setup(const toml::table& file, const toml::table& entry) {
  const std::string effect =
      entry["effect"].value_or(file["effect"].value_or(std::string("normal")));
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

// Runs the [[case]] references (or rewrites them under RICOCHET_REGENERATE) and the [[trend]]
// physics of one file; returns the effects its entries cover.
std::set<std::string> run_file(const fs::path& path) {
  std::set<std::string> covered;
  const toml::table file = toml::parse_file(path.string());
  const bool regenerate = std::getenv("RICOCHET_REGENERATE") != nullptr;
  std::vector<std::string> fresh;
  const toml::array* cases = file["case"].as_array();
  EXPECT_TRUE(cases && !cases->empty()) << path;
  if (!cases) return covered;
  for (const auto& node : *cases) {
    const toml::table& entry = *node.as_table();
    const CaseSetup run = setup(file, entry);
    covered.insert(entry["effect"].value_or(file["effect"].value_or(std::string())));
    const auto r = simulate(run.model, run.shape, run.c);
    EXPECT_EQ(r.status, CollisionStatus::kOk) << path << " line " << entry.source().begin.line;
    std::ostringstream s;
    s.precision(10);
    s << "vout = [" << r.vout[0] << ", " << r.vout[1] << ", " << r.vout[2] << "]";
    fresh.push_back(s.str());
    const toml::array* ref = entry["vout"].as_array();
    if (regenerate) continue;
    EXPECT_TRUE(ref && ref->size() == 3)
        << path << ": no reference; run with RICOCHET_REGENERATE=1";
    if (!ref || ref->size() != 3) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      const double want = *ref->get(k)->value<double>();
      EXPECT_NEAR(r.vout[k], want, 1e-6 * (1.0 + std::fabs(want)))
          << path << " line " << entry.source().begin.line << " component " << k;
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
  return covered;
}

class EffectCases : public ::testing::TestWithParam<std::string> {};

TEST_P(EffectCases, ReferencesAndTrends) {
  const fs::path path = kSource / "tests/engine/effects" / (GetParam() + ".toml");
  ASSERT_TRUE(fs::exists(path)) << "every registered effect needs a test file: " << path;
  ASSERT_TRUE(fs::exists(kSource / "docs/effects" / (GetParam() + ".md")))
      << "every registered effect needs a doc page docs/effects/" << GetParam() << ".md";
  ASSERT_EQ(toml::parse_file(path.string())["effect"].value_or(std::string()), GetParam());
  run_file(path);
}

std::vector<std::string> registered(bool generated) {
  std::vector<std::string> out;
  const EffectRegistry r = EffectRegistry::with_builtins();
  for (const auto& n : r.names())
    if (r.get(n).generated() == generated) out.push_back(n);
  return out;
}

INSTANTIATE_TEST_SUITE_P(Registry, EffectCases, ::testing::ValuesIn(registered(false)),
                         [](const auto& info) { return info.param; });

// The generated family: one page that documents every coefficient, variable and form, one file
// with a reference case for every generated law (more physics in coefficient_law_test.cpp).
TEST(EffectCases, GeneratedFamilySharesOnePageAndOneFile) {
  const fs::path page = kSource / "docs/effects/coefficient_law.md";
  ASSERT_TRUE(fs::exists(page)) << "the generated coefficient laws need " << page;
  std::ifstream in(page);
  std::stringstream text;
  text << in.rdbuf();
  const EffectRegistry r = EffectRegistry::with_builtins();
  const std::set<std::string> covered =
      run_file(kSource / "tests/engine/effects/coefficient_law.toml");
  for (const auto& name : registered(true)) {
    if (name.starts_with("term_")) continue;  // the force terms: the test below
    const auto config = effects::parse_coefficient_law_name(name);
    ASSERT_TRUE(config) << name << " is generated but not a coefficient law";
    for (std::string_view part : {config->coefficient, config->variable, config->form})
      EXPECT_NE(text.str().find("`" + std::string(part) + "`"), std::string::npos)
          << page << " does not document `" << part << "` (" << name << ")";
    EXPECT_TRUE(covered.count(name)) << "no case for " << name << " in coefficient_law.toml";
  }
}

// The force terms: one page that documents every term, one file with a case for every term.
TEST(EffectCases, ForceTermsShareOnePageAndOneFile) {
  const fs::path page = kSource / "docs/effects/force_term.md";
  ASSERT_TRUE(fs::exists(page)) << "the force terms need " << page;
  std::ifstream in(page);
  std::stringstream text;
  text << in.rdbuf();
  const std::set<std::string> covered = run_file(kSource / "tests/engine/effects/force_term.toml");
  std::size_t terms = 0;
  for (const auto& name : registered(true)) {
    if (!name.starts_with("term_")) continue;
    ++terms;
    EXPECT_NE(text.str().find("`" + name.substr(5) + "`"), std::string::npos)
        << page << " does not document " << name;
    EXPECT_TRUE(covered.count(name)) << "no case for " << name << " in force_term.toml";
  }
  EXPECT_EQ(terms, effects::force_terms().size());
}

}  // namespace
}  // namespace ricochet
