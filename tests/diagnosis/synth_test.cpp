// ricochet synth (diagnosis/synth.hpp): reproducibility, noise, designs, schema, and that the
// truth never reaches the data file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "diagnosis/synth.hpp"
#include "engine/engine.hpp"

namespace ricochet::diagnosis {
namespace {

namespace fs = std::filesystem;

Model truth_with_rate() {
  Model m = Model::paper().with_effect("rate_restitution");
  m.set("kv", 0.2);
  m.set("en2", 0.3);
  return m;
}

SynthOptions wide(std::size_t n, std::uint64_t seed) {
  SynthOptions o;
  o.n = n;
  o.seed = seed;
  o.design = Design::kWide;
  return o;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Synth, SameSeedSameSetBitForBit) {
  const Model m = truth_with_rate();
  const auto a = synthesize(m, Shape::cylinder(), wide(12, 7));
  const auto b = synthesize(m, Shape::cylinder(), wide(12, 7));
  EXPECT_EQ(format_impact_set_csv(a.set), format_impact_set_csv(b.set));
  const auto c = synthesize(m, Shape::cylinder(), wide(12, 8));
  EXPECT_NE(format_impact_set_csv(a.set), format_impact_set_csv(c.set));
}

TEST(Synth, WithoutNoiseTheSetIsTheEngineOutput) {
  const Model m = truth_with_rate();
  SynthOptions o = wide(6, 3);
  o.noise = NoiseSpec::none();
  const auto r = synthesize(m, Shape::cylinder(), o);
  ASSERT_EQ(r.set.size(), 6u);
  for (const auto& im : r.set.impacts) {
    CollisionCase c{im.vin, 0.0};
    const CollisionResult s = simulate(m, Shape::cylinder(), c, {}, o.engine);
    for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(im.vout[k], s.vout[k]) << im.id;
    ASSERT_TRUE(im.penetration && im.contact_duration);
    EXPECT_DOUBLE_EQ(*im.penetration, s.max_penetration_m);
    EXPECT_DOUBLE_EQ(*im.contact_duration, s.contact_duration_s);
    ASSERT_TRUE(im.sigma_vout.has_value());
    EXPECT_EQ((*im.sigma_vout)[1], 0.0);
    // Wide design box.
    EXPECT_GE(im.vin[0], 1.5);
    EXPECT_LE(im.vin[0], 6.0);
    EXPECT_GE(im.vin[1], -5.0);
    EXPECT_LE(im.vin[1], -1.0);
  }
}

TEST(Synth, LabNoiseHasTheDeclaredSpread) {
  // Residuals of noisy against exact outputs over many releases: sample sd close to the spec.
  const Model m = Model::paper();
  SynthOptions noisy = wide(300, 5);
  noisy.write_penetration = noisy.write_contact_duration = false;
  const auto a = synthesize(m, Shape::cylinder(), noisy);
  ASSERT_EQ(a.set.size(), 300u);
  // Measured V_in against the true V_in kept in the provenance.
  Vel3 sq{};
  for (std::size_t i = 0; i < a.set.size(); ++i) {
    const auto& t = a.truth["releases"][i]["vin"];
    for (int k = 0; k < 3; ++k) {
      const double d = a.set.impacts[i].vin[k] - t[k].get<double>();
      sq[k] += d * d / 300.0;
    }
  }
  const NoiseSpec lab = NoiseSpec::lab();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(std::sqrt(sq[k]), lab.vin[k], 0.15 * lab.vin[k]) << k;
  }
}

TEST(Synth, LabDesignResamplesTheLabIncidentStates) {
  SynthOptions o;
  o.n = 200;
  o.incident = lab_incident_states(Shape::cylinder());
  ASSERT_EQ(o.incident.size(), 28u);
  const auto r = synthesize(Model::paper(), Shape::cylinder(), o);
  double mx = 0, my = 0, mw = 0;
  for (const auto& im : r.set.impacts)
    mx += im.vin[0] / 200, my += im.vin[1] / 200, mw += im.vin[2] / 200;
  // Paper Table 2 means: 2.87 m/s, -2.34 m/s, -65.03 rad/s.
  EXPECT_NEAR(mx, 2.87, 0.1);
  EXPECT_NEAR(my, -2.34, 0.1);
  EXPECT_NEAR(mw, -65.0, 2.5);
}

TEST(Synth, TrianglesCarryTheirOrientationUnlessAskedNotTo) {
  SynthOptions o = wide(5, 2);
  const auto a = synthesize(Model::paper(), Shape::triangle(), o);
  for (const auto& im : a.set.impacts) {
    ASSERT_TRUE(im.alpha_in.has_value());
    EXPECT_LE(std::fabs(*im.alpha_in), M_PI / 3 + 1e-12);
    EXPECT_EQ(im.shape, "triangle");
  }
  o.write_alpha = false;
  const auto b = synthesize(Model::paper(), Shape::triangle(), o);
  for (const auto& im : b.set.impacts) EXPECT_FALSE(im.alpha_in.has_value());
}

TEST(Synth, PerReleaseScatterMovesTheTrueParameters) {
  SynthOptions o = wide(40, 4);
  o.scatter = {{"en2", 0.05}};
  const auto r = synthesize(Model::paper(), Shape::cylinder(), o);
  double mean = 0, sq = 0;
  for (const auto& t : r.truth["releases"]) mean += t["params"]["en2"].get<double>() / 40;
  for (const auto& t : r.truth["releases"])
    sq += std::pow(t["params"]["en2"].get<double>() - mean, 2) / 39;
  EXPECT_NEAR(std::sqrt(sq), 0.05, 0.02);
  EXPECT_NEAR(mean, 0.15, 0.03);
}

TEST(Synth, TheTruthIsNotInTheDataFile) {
  const Model m = truth_with_rate();
  const auto r = synthesize(m, Shape::cylinder(), wide(8, 9));
  const fs::path dir = fs::temp_directory_path() / ("ricochet-synth-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_impact_set(r.set, (dir / "s.csv").string());
  write_impact_set(r.set, (dir / "s.h5").string());
  const std::string csv = slurp(dir / "s.csv");
  for (const char* secret : {"rate_restitution", "kv", "tangential", "en2", "normal"})
    EXPECT_EQ(csv.find(secret), std::string::npos) << "the CSV contains " << secret;
  // Binary doubles could hold any short byte pair by chance: only the names are checked.
  const std::string h5 = slurp(dir / "s.h5");
  ASSERT_FALSE(h5.empty());
  for (const char* secret : {"rate_restitution", "tangential", "rolling"})
    EXPECT_EQ(h5.find(secret), std::string::npos) << "the HDF5 file contains " << secret;
  // The provenance carries it, separately.
  EXPECT_NE(r.truth.dump().find("rate_restitution"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Synth, NoiseSpecParsing) {
  const NoiseSpec a = NoiseSpec::parse("lab,contact_duration=2e-4");
  EXPECT_EQ(a.vout[2], 3.4);
  EXPECT_EQ(a.contact_duration_s, 2e-4);
  const NoiseSpec b = NoiseSpec::parse("vout_y=0.05,scale=2");
  EXPECT_EQ(b.vout[1], 0.1);
  EXPECT_EQ(b.vout[0], 0.0);
  EXPECT_EQ(NoiseSpec::parse("none").vin[0], 0.0);
  for (const char* bad : {"", "loud", "vout_y=-1", "vout_y=x", "vout_z=1", "vout_y=1,lab"}) {
    try {
      (void)NoiseSpec::parse(bad, "--noise");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "--noise") << bad;
    }
  }
}

TEST(Synth, BadOptionsAreRefused) {
  SynthOptions o = wide(0, 1);
  EXPECT_THROW(synthesize(Model::paper(), Shape::cylinder(), o), InputError);
  o.n = 3;
  o.scatter = {{"nope", 0.1}};
  EXPECT_THROW(synthesize(Model::paper(), Shape::cylinder(), o), std::invalid_argument);
  SynthOptions lab;
  lab.n = 3;  // lab design without incident states
  EXPECT_THROW(synthesize(Model::paper(), Shape::cylinder(), lab), std::invalid_argument);
}

}  // namespace
}  // namespace ricochet::diagnosis
