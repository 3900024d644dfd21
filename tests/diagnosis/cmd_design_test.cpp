// `ricochet design` run as a program: bad options exit 2 naming the option (before any work),
// and the plan it writes reads back through the impact-set reader as a set of incident states
// inside the box, with the JSON document's pairs and rivals.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "impact/impact_set.hpp"
#include "support/program_test.hpp"

namespace ricochet {
namespace {

using test::quote;
using test::RunResult;

const std::string kCyl = quote(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");

class CmdDesign : public test::ProgramTest {};

TEST_F(CmdDesign, BadOptionsExitTwoNamingTheOption) {
  const std::string out = " --out " + quote((dir_ / "plan.csv").string());
  const std::string base = "design " + kCyl + " --rivals none,rate_restitution" + out;
  struct Case {
    std::string args, says;
  };
  const std::vector<Case> cases = {
      {base + " --range vin_y=-1:-5", "expected LO <= HI"},  // A > B: empty
      {base + " --range speed=1:2", "unknown component"},    // not a component
      {base + " --range vin_y=-2:1", "below 0"},             // the block must fall
      {base + " --range vin_x=1", "expected NAME=A:B"},      // malformed
      {base + " --range vin_x=a:2", "not a finite number"},  // not a number
      {base + " --budget 0", "field '--budget': value 0 is outside [1, 10000]"},
      {base + " --budget 10001", "field '--budget': value 10001 is outside [1, 10000]"},
      {base + " --budget 50 --candidates 10", "--candidates"},
      {base + " --alpha 0.9", "--alpha"},
      {"design " + kCyl + " --rivals none,bogus" + out, "unknown rival 'bogus'"},
      {"design " + kCyl + " --rivals none" + out, "--rivals"},
      {"design " + kCyl + " --rivals none,rate_restitution --out plan.h5", "--out"},
      {"design " + kCyl + " --rivals none,rate_restitution --out plan.json", "use one of .csv"},
      {"design " + kCyl + " --rivals none,rate_restitution", "--out"},  // required
  };
  for (const Case& c : cases) {
    const RunResult r = ricochet(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << "\nstderr: " << r.err;
    EXPECT_TRUE(r.out.empty()) << c.args << "\nstdout: " << r.out;
  }
  // The unknown rival's message lists the known names.
  const RunResult r = ricochet("design " + kCyl + " --rivals none,bogus" + out);
  EXPECT_NE(r.err.find("inertial_drag"), std::string::npos) << r.err;
}

TEST_F(CmdDesign, ThePlanReadsBackAsIncidentStates) {
  const std::string plan = (dir_ / "plan.csv").string();
  const RunResult r =
      ricochet("design " + kCyl +
               " --shape cylinder --rivals none,rate_restitution,inertial_drag --budget 8 "
               "--candidates 128 --range vin_x=2:4.5 --range vin_y=-4:-1.5 --range win=-90:-20 "
               "--seed 2 --json --out " +
               quote(plan));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc.at("command"), "design");
  EXPECT_EQ(doc.at("budget"), 8);
  EXPECT_EQ(doc.at("rivals").size(), 3u);
  EXPECT_EQ(doc.at("pairs").size(), 3u);
  EXPECT_EQ(doc.at("plan").size(), 8u);
  for (const auto& p : doc.at("pairs")) {
    EXPECT_TRUE(p.at("plan").contains("power"));
    EXPECT_TRUE(p.at("uniform").contains("lambda"));
  }
  EXPECT_TRUE(doc.at("rivals").at(1).at("law").is_string());
  // Every top-level key is documented (docs/commands/design.md, "JSON keys"; the three every
  // document carries in docs/commands/README.md), as tests/cli checks for the other commands.
  const std::string page =
      test::slurp(std::string(RICOCHET_SOURCE_DIR) + "/docs/commands/design.md");
  const std::size_t from = page.find("## JSON keys");
  ASSERT_NE(from, std::string::npos);
  const std::string section = page.substr(from, page.find("\n## ", from + 1) - from);
  for (const auto& [key, value] : doc.items()) {
    if (key == "command" || key == "version" || key == "input_files") continue;
    EXPECT_TRUE(section.find("`" + key + "`") != std::string::npos ||
                section.find("\"" + key + "\"") != std::string::npos)
        << "key " << key << " is not documented in docs/commands/design.md";
  }

  // Through the impact-set reader: incident states only, every other rule of the schema.
  const ImpactSet set = read_incident_states(plan);
  ASSERT_EQ(set.size(), 8u);
  for (std::size_t i = 0; i < set.size(); ++i) {
    const Impact& im = set.impacts[i];
    EXPECT_EQ(im.shape, "cylinder");
    EXPECT_TRUE(std::isnan(im.vout[kVx]) && std::isnan(im.vout[kVy]) && std::isnan(im.vout[kW]));
    EXPECT_GE(im.vin[kVx], 2.0);
    EXPECT_LE(im.vin[kVx], 4.5);
    EXPECT_GE(im.vin[kVy], -4.0);
    EXPECT_LE(im.vin[kVy], -1.5);
    EXPECT_GE(im.vin[kW], -90.0);
    EXPECT_LE(im.vin[kW], -20.0);
    EXPECT_EQ(im.vin[kVx], doc.at("plan").at(i).at("vin_x").get<double>());  // shortest form
  }
  EXPECT_FALSE(set.comments.empty());
  // The full impact-set reader still asks for the reflected velocity.
  EXPECT_THROW(read_impact_set(plan), InputError);
  // The same inputs give the same plan bit for bit.
  const std::string again = (dir_ / "again.csv").string();
  const RunResult r2 =
      ricochet("design " + kCyl +
               " --shape cylinder --rivals none,rate_restitution,inertial_drag --budget 8 "
               "--candidates 128 --range vin_x=2:4.5 --range vin_y=-4:-1.5 --range win=-90:-20 "
               "--seed 2 --threads 1 --out " +
               quote(again));
  ASSERT_EQ(r2.status, 0) << r2.err;
  EXPECT_EQ(test::slurp(again), test::slurp(plan));
}

TEST(IncidentStates, TheReaderKeepsTheSchemaRules) {
  const std::string ok = "id,shape,vin_x[cm/s],vin_y[m/s],win[rad/s]\nD1,cylinder,250,-2,-60\n";
  const ImpactSet s = parse_incident_states_csv(ok, "plan.csv");
  ASSERT_EQ(s.size(), 1u);
  EXPECT_DOUBLE_EQ(s.impacts[0].vin[kVx], 2.5);  // units converted as in any impact set
  const auto error = [](const std::string& text) {
    try {
      parse_incident_states_csv(text, "plan.csv");
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("id,shape,vin_x[m/s],vin_y[m/s],win[rad/s]\nD1,cylinder,2,1,-60\n"), "vin_y");
  EXPECT_EQ(error("id,shape,vin_x[m/s],win[rad/s]\nD1,cylinder,2,-60\n"), "vin_y");
  EXPECT_EQ(error("id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s]\nD1,cylinder,2,-1,-6,1\n"),
            "vout_y");  // the reflected columns come together
  EXPECT_EQ(
      error(
          "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s]\nD1,cylinder,2,-1,-6\nD1,cylinder,2,-1,-6\n"),
      "id");
  // A full impact set reads as incident states too, with its own checks.
  const ImpactSet full = parse_incident_states_csv(
      "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s]\n"
      "C1,cylinder,2.5,-2.6,-68,3.3,0.9,-40\n",
      "set.csv");
  EXPECT_DOUBLE_EQ(full.impacts[0].vout[kVy], 0.9);
}

}  // namespace
}  // namespace ricochet
