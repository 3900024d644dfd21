// The force-residual discovery's rates on the independent simulator (issue 33, item 4), on seeds
// fixed in docs/detection-benchmark.md before the run: for each hidden force, the share of sets in
// which a term of its family is selected, and without a hidden force the share in which nothing
// (or nothing in a component) is selected, each with its Wilson 95 % interval, for the two ways
// of making the residual (force_sets.hpp): the hidden force given directly, and the measured force
// minus the engine's law along the measured path.
//
//   force_discovery_study --first-null 3001 --nulls 100 --first-seed 4001 --seeds 10 --out FILE.tsv
//
// One line per set in FILE.tsv (way, family, seed, the selected terms per component); the summary
// on stdout, as docs/detection-benchmark.md quotes it.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <array>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "diagnosis/force_law.hpp"
#include "force_sets.hpp"
#include "stats/stats.hpp"

namespace {

using namespace ricochet;
using namespace ricochet::truth;

struct Hidden {
  truth::Family family;
  double strength;
  std::set<std::string> terms;  // the library's terms of the family
};

// The test's strengths and families (force_discovery_test.cpp): the Katsuragi-Durian drag at its
// lab scale (m/d1 = 40 kg/m), the depth-speed drag at 40 kg/m at 3 mm, the Rankine ploughing at
// the wide design's detection-study strength (c = 1.73e8 N/m^2), the rate-threshold drag at
// c_rt = 100 kg/m above 2 m/s (400 N at 4 m/s).
const std::vector<Hidden> kHidden = {
    {truth::Family::kKdDrag, 1.0, {"inertial_drag", "viscous", "depth_drag"}},
    {truth::Family::kDepthSpeedDrag, 1.0, {"depth_drag", "inertial_drag"}},
    {truth::Family::kRankinePlough, 20568.2, {"ploughing"}},
    {truth::Family::kRateThresholdDrag, 1.0, {"inertial_drag", "viscous", "depth_drag"}},
};

// The two ways of making the residual (force_sets.hpp), as the TSV names them.
const std::vector<std::pair<std::string, SetMaker>> kWays = {
    {"hidden", traced_set}, {"through_law", traced_set_through_law}};

std::string by_component(const std::vector<diagnosis::ComponentLaw>& laws,
                         diagnosis::ForceComponent c) {
  std::string s;
  for (const auto& law : laws)
    if (law.component == c)
      for (const auto& t : law.terms)
        if (t.selected) s += (s.empty() ? "" : "+") + std::string(t.term->name);
  return s.empty() ? "-" : s;
}

std::string rate(std::size_t k, std::size_t n) {
  const auto p = stats::wilson(k, n);
  return fmt::format("{}/{} = {:.2f} [{:.2f}, {:.2f}]", k, n, p.rate, p.lo, p.hi);
}

// The power curve (--power): at each multiple of a family's test strength, the share of sets in
// which the discovery selects a term of the family, each way, beside the oracle's (oracle_z > the
// one-sided 5 % point 1.645, on the same set as the `hidden` way) and its mean z.
int power_curve(std::ofstream& tsv, const std::vector<std::vector<double>>& factors,
                std::uint64_t first_seed, std::size_t seeds, bool oracle_only) {
  tsv << "family\tfactor\tstrength\tseed\toracle_z\tfound_hidden\tfound_through_law\n";
  std::cout << fmt::format(
      "power curve of the force-residual discovery: 30 wide-design releases per set, 50 N force "
      "noise, seeds {}-{} per level; oracle: the exact shape's one coefficient, one-sided 5 %\n",
      first_seed, first_seed + seeds - 1);
  std::cout << "| family | x test strength | oracle mean z | oracle power | found, hidden | found, "
               "through the law |\n| :-- | --: | --: | :-- | :-- | :-- |\n";
  for (std::size_t k = 0; k < kHidden.size(); ++k)
    for (double factor : factors[k]) {
      const Hidden& h = kHidden[k];
      const double strength = h.strength * factor;
      double z_sum = 0;
      std::size_t oracle = 0;
      std::array<std::size_t, 2> found{};
      for (std::uint64_t s = first_seed; s < first_seed + seeds; ++s) {
        const double z = oracle_z(h.family, strength, s);
        z_sum += z;
        oracle += z > 1.645;
        std::array<int, 2> hit{-1, -1};
        if (!oracle_only)
          for (std::size_t w = 0; w < kWays.size(); ++w) {
            hit[w] = finds(discover(kWays[w].second, h.family, strength, s), h.terms);
            found[w] += hit[w];
          }
        tsv << fmt::format("{}\t{}\t{}\t{}\t{:.3f}\t{}\t{}\n", family_name(h.family), factor,
                           strength, s, z, hit[0], hit[1]);
      }
      std::cout << fmt::format("| {} | {:.4g} | {:.1f} | {} | {} | {} |\n", family_name(h.family),
                               factor, z_sum / static_cast<double>(seeds), rate(oracle, seeds),
                               oracle_only ? "-" : rate(found[0], seeds),
                               oracle_only ? "-" : rate(found[1], seeds));
    }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Rates of the force-residual discovery on the independent simulator (issue 33)"};
  std::uint64_t first_null = 3001, first_seed = 4001;
  std::size_t nulls = 100, seeds = 10;
  std::string out;
  app.add_option("--first-null", first_null, "First seed of the null sets");
  app.add_option("--nulls", nulls, "Null sets")->check(CLI::Range(1, 100000));
  app.add_option("--first-seed", first_seed, "First seed of the sets with a hidden force");
  app.add_option("--seeds", seeds, "Sets per hidden force")->check(CLI::Range(1, 100000));
  app.add_option("--out", out, "One line per set (TSV)")->required();
  std::vector<double> factors, levels;
  bool oracle_only = false;
  std::uint64_t probe_seed = 4001;
  app.add_option("--power", factors,
                 "Instead of the rates at the test's strengths: the power curve at these "
                 "multiples of them (hidden-force seeds only, with the oracle's z per set)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  app.add_option("--power-z", levels,
                 "The power curve at the strengths where the oracle's mean z is about these "
                 "values: each family's multiple is level / (its oracle mean z at the test "
                 "strength on the 10 probe seeds)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber)
      ->excludes("--power");
  app.add_option("--probe-seed", probe_seed, "First of the 10 probe seeds of --power-z");
  app.add_flag("--oracle-only", oracle_only, "With --power: the oracle's z alone (no discovery)");
  CLI11_PARSE(app, argc, argv);

  std::ofstream tsv(out);
  if (!tsv) {
    std::cerr << "force_discovery_study: cannot write " << out << "\n";
    return 2;
  }
  if (!factors.empty() || !levels.empty()) {
    std::vector<std::vector<double>> per_family;
    for (const Hidden& h : kHidden) {
      if (levels.empty()) {
        per_family.push_back(factors);
        continue;
      }
      // The oracle's z grows about linearly with the strength (it is the coefficient's
      // signal-to-noise ratio): one probe at the test strength places every level.
      double z1 = 0;
      for (std::uint64_t s = probe_seed; s < probe_seed + 10; ++s)
        z1 += oracle_z(h.family, h.strength, s) / 10;
      std::vector<double> f;
      for (double level : levels) f.push_back(level / z1);
      per_family.push_back(f);
    }
    return power_curve(tsv, per_family, first_seed, seeds, oracle_only);
  }
  tsv << "way\tfamily\tseed\tnormal\ttangential\n";
  std::cout << fmt::format(
      "force-residual discovery on the independent simulator: 30 wide-design releases per set, "
      "50 N force noise; null seeds {}-{}, hidden-force seeds {}-{}\n",
      first_null, first_null + nulls - 1, first_seed, first_seed + seeds - 1);
  for (const auto& [way, make] : kWays) {
    std::size_t clean = 0, normal_clean = 0, tangential_clean = 0;
    for (std::uint64_t s = first_null; s < first_null + nulls; ++s) {
      const auto laws = discover(make, truth::Family::kNone, 0, s);
      const std::string n = by_component(laws, diagnosis::ForceComponent::kNormal);
      const std::string t = by_component(laws, diagnosis::ForceComponent::kTangential);
      clean += n == "-" && t == "-";
      normal_clean += n == "-";
      tangential_clean += t == "-";
      tsv << way << "\tnone\t" << s << "\t" << n << "\t" << t << "\n";
    }
    std::cout << fmt::format(
        "{}: null sets with nothing found {}; normal clean {}; tangential "
        "clean {}\n",
        way, rate(clean, nulls), rate(normal_clean, nulls), rate(tangential_clean, nulls));
    for (const Hidden& h : kHidden) {
      std::size_t found = 0;
      for (std::uint64_t s = first_seed; s < first_seed + seeds; ++s) {
        const auto laws = discover(make, h.family, h.strength, s);
        found += finds(laws, h.terms);
        tsv << way << "\t" << family_name(h.family) << "\t" << s << "\t"
            << by_component(laws, diagnosis::ForceComponent::kNormal) << "\t"
            << by_component(laws, diagnosis::ForceComponent::kTangential) << "\n";
      }
      std::cout << fmt::format("{}: {} found {}\n", way, family_name(h.family), rate(found, seeds));
    }
  }
  return 0;
}
