// Upscaling without LIGGGHTS: a campaign file whose "resolved" rebounds were produced by the
// reduced engine itself with a known e_n^2 per grain stiffness. Upscaling must group the impacts
// by the grain parameter that varies (not by the replica seed), and recover each group's e_n^2.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "campaign.hpp"
#include "common/error.hpp"
#include "dem_support.hpp"
#include "effects/model.hpp"
#include "fit/fit.hpp"
#include "upscale.hpp"

namespace {

using namespace ricochet;
using namespace ricochet::dem;
namespace fs = std::filesystem;

using test::decks;

const std::vector<Vel3> kIncident = {{2.9, -2.3, -65.0}, {2.6, -2.5, -70.0}, {3.2, -2.1, -60.0}};

// Appends to the campaign file `path` "resolved" impacts made by the reduced engine with the
// truth model: kIncident x replica seeds 0 and 1 (seed 0 shifted by -offset, seed 1 by +offset),
// ids PREFIX-vK-sS, with the bed parameter `bed_name` = `bed_value` when given.
void append_synthetic(const std::string& path, const Model& truth, const std::string& prefix,
                      const std::string& bed_name, const std::string& bed_value,
                      const Vel3& offset) {
  ImpactSet set;
  for (const auto& v : kIncident) {
    Impact im;
    im.id = "x";
    im.shape = "cylinder";
    im.vin = v;
    im.vout = {1.0, 1.0, -1.0};
    set.impacts.push_back(im);
  }
  const auto pred = fit::predict(truth, Shape::cylinder(), truth.values(), set);
  for (std::size_t k = 0; k < kIncident.size(); ++k)
    for (int seed = 0; seed < 2; ++seed) {
      ImpactSpec spec;
      spec.id = prefix + "-v" + std::to_string(k) + "-s" + std::to_string(seed);
      spec.vin = kIncident[k];
      spec.seed = seed;
      if (!bed_name.empty()) spec.params.bed[bed_name] = bed_value;
      ImpactResult r;
      r.id = spec.id;
      r.status = "rebound";
      r.impact.id = spec.id;
      r.impact.shape = "cylinder";
      r.impact.vin = kIncident[k];
      r.impact.vout = pred[k].vout;
      for (int c = 0; c < 3; ++c) r.impact.vout[c] += (seed == 0 ? -1.0 : 1.0) * offset[c];
      r.impact.extra.assign(impact_extra_names().size(), 0.0);
      append_result(path, r, spec, "synthetic");
    }
}

// A fresh, empty directory for one test, unique to this process.
fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("dem-upscale" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(Upscale, GroupsByTheVaryingGrainParameterAndRecoversEachGroupsRestitution) {
  const fs::path dir = fresh_dir("");
  const std::string path = (dir / "campaign.h5").string();
  const Shape shape = Shape::cylinder();
  const Model paper = Model::paper();
  // Two "grain stiffnesses", each with its own true e_n^2; three incident states and two
  // replica seeds each.
  const std::vector<std::pair<std::string, double>> truth = {{"1e+08", 0.10}, {"4e+08", 0.30}};
  for (const auto& [stiffness, en2] : truth) {
    Model m = paper;
    m.set("en2", en2);
    append_synthetic(path, m, "E" + stiffness, "E_grain_Pa", stiffness, {0.0, 0.0, 0.0});
  }

  UpscaleOptions o;
  o.fit.intervals = true;
  o.fit.threads = 1;
  const UpscaleResult r = upscale(path, decks(), paper, shape, o);
  ASSERT_EQ(r.impacts.size(), 12u);
  // The replicas are identical here (the reduced engine is deterministic): no noise estimate
  // from them, the intervals use the lab's operator scale.
  EXPECT_EQ(r.noise_source, "table1");
  EXPECT_EQ(r.noise_sigma, o.fit.sigma);
  ASSERT_EQ(r.by, std::vector<std::string>{"bed.E_grain_Pa"});  // the seed is not a group
  ASSERT_EQ(r.groups.size(), 2u);
  for (const auto& g : r.groups) {
    EXPECT_EQ(g.members.size(), 6u);
    const double expected = g.grain.at("bed.E_grain_Pa") == "1e+08" ? 0.10 : 0.30;
    const auto i = paper.index("en2");
    EXPECT_NEAR(g.population.params[i], expected, 0.01) << g.key;
    for (std::size_t m : g.members) EXPECT_NEAR(r.impacts[m].fit.params[i], expected, 0.02);
    // e_n^2 is identified (paper section 4.4: it alone drives V_out^y).
    for (const auto& iv : g.population.intervals)
      if (iv.name == "en2") {
        EXPECT_EQ(iv.status, fit::Identifiability::kIdentified) << iv.statement;
        EXPECT_LE(iv.lo, expected);
        EXPECT_GE(iv.hi, expected);
      }
  }
  ASSERT_TRUE(r.campaign.has_value());

  // Grouping by a parameter that does not vary gives one group; an unknown one is an error.
  o.by = {"bed.mu_gg"};
  EXPECT_EQ(upscale(path, decks(), paper, shape, o).groups.size(), 1u);
  o.by = {"bed.stiffness"};
  EXPECT_THROW(upscale(path, decks(), paper, shape, o), InputError);

  const auto files = write_upscale_figures(r, (dir / "fig").string());
  EXPECT_EQ(files.size(), 2u);  // parameters vs incident state, abacus against E_grain_Pa
  for (const auto& f : files) EXPECT_GT(fs::file_size(f), 1000u);
  fs::remove_all(dir);
}

// With lab releases, upscale calibrates them per release with the same engine: resolved and lab
// parameters side by side. Here the "lab" has e_n^2 = 0.30 and the campaign 0.10; each side must
// come out as its own, not as the other.
TEST(Upscale, LabReleasesAreCalibratedWithTheSameEngine) {
  const fs::path dir = fresh_dir("-lab");
  const std::string path = (dir / "campaign.h5").string();
  const Model paper = Model::paper();
  Model resolved = paper, measured = paper;
  resolved.set("en2", 0.10);
  measured.set("en2", 0.30);
  append_synthetic(path, resolved, "r", "", "", {0.0, 0.0, 0.0});
  ImpactSet lab;
  for (std::size_t k = 0; k < kIncident.size(); ++k) {
    Impact im;
    im.id = "L" + std::to_string(k);
    im.shape = "cylinder";
    im.vin = kIncident[k];
    lab.impacts.push_back(im);
  }
  const auto pred = fit::predict(measured, Shape::cylinder(), measured.values(), lab);
  for (std::size_t k = 0; k < lab.size(); ++k) lab.impacts[k].vout = pred[k].vout;

  UpscaleOptions o;
  o.fit.intervals = false;
  o.fit.threads = 1;
  o.lab = &lab;
  const UpscaleResult r = upscale(path, decks(), paper, Shape::cylinder(), o);
  const auto i = paper.index("en2");
  ASSERT_EQ(r.lab_fits.size(), lab.size());
  for (const auto& f : r.lab_fits) EXPECT_NEAR(f.params[i], 0.30, 0.02);
  for (const auto& u : r.impacts) EXPECT_NEAR(u.fit.params[i], 0.10, 0.02);
  const auto files = write_upscale_figures(r, (dir / "fig").string());
  EXPECT_NE(std::find_if(
                files.begin(), files.end(),
                [](const std::string& f) { return f.ends_with("upscale_parameters_vs_lab.svg"); }),
            files.end());
  fs::remove_all(dir);
}

// Replicas (here: two seeds of each incident state) that scatter give the noise of the intervals:
// the campaign file labels them as replicates, and upscale pools their scatter.
TEST(Upscale, ScatterOfReplicasIsTheNoiseOfTheIntervals) {
  const fs::path dir = fresh_dir("-noise");
  const std::string path = (dir / "campaign.h5").string();
  const Model paper = Model::paper();
  const Vel3 offset = {0.05, 0.02, 1.0};  // replica s0 at -offset, s1 at +offset
  append_synthetic(path, paper, "p", "", "", offset);
  UpscaleOptions o;
  o.fit.intervals = false;
  o.fit.threads = 1;
  const UpscaleResult r = upscale(path, decks(), paper, Shape::cylinder(), o);
  EXPECT_EQ(r.noise_source, "replicates");
  // Pooled SD over 3 pairs at +-offset: sqrt(3 * 2 offset^2 / 3) = sqrt(2) offset.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.noise_sigma[c], std::sqrt(2.0) * offset[c], 1e-9);
  fs::remove_all(dir);
}

}  // namespace
