// `detection_summary DIR`: the detection benchmark's table (docs/detection-benchmark.md) from
// the files NAME.truth.json (independent_truth) and NAME.diagnose.json (ricochet diagnose
// --json), and for "two" also NAME.ladder.json (ricochet ladder --auto 2 --json), in DIR.
//
// Per cell (family, strength, n, design):
//   detected        the top-ranked candidate is SUPPORTED and names the hidden family
//                   (truth::candidate_family: the benchmark's one mapping), Wilson 95 % interval
//   any supported   anything at all supported; on null sets this is the false-alarm rate
//   found           the family of the top supported candidate, counted (what was found instead)
//   effect size     mean and RMS V_out shift and the RMS left after refitting the paper's
//                   constants (physical units, from the truth files), mean over the cell's sets
//   oracle          mean over the cell's sets of the oracle's z and of its power for one
//                   hypothesis and for the Bonferroni family (truth_sim.hpp, "The oracle's
//                   ceiling": no test can do better); "-" (JSON null) when the cell's truth files
//                   predate the oracle (no "oracle" key)
//   verdicts        counts; and how often the verdict agrees with the ranking
//   both found      "two" only: the two ladder rounds added one law of each family
// Writes the markdown on stdout and DIR/summary.json. Exit 2 on bad usage, 1 when DIR has no
// complete pair.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <tuple>

#include <fmt/format.h>

#include "stats/stats.hpp"
#include "truth_sim.hpp"

namespace fs = std::filesystem;
using namespace ricochet;
using nlohmann::json;

namespace {

struct Cell {
  std::size_t sets = 0, right = 0, any = 0, consistent = 0, ladders = 0, both = 0;
  std::map<std::string, std::size_t> verdicts, found;
  std::array<double, 3> mean{}, rms{}, residual{};
  double lab_units = 0, seconds = 0;
  std::size_t oracle_sets = 0;  // sets whose truth has an "oracle"
  double oracle_z = 0, oracle_single = 0, oracle_family = 0;
};

std::array<double, 3> vec3(const json& j, const char* key) {
  std::array<double, 3> v{};
  if (j.contains(key) && j[key].is_array() && j[key].size() == 3)
    for (int k = 0; k < 3; ++k) v[k] = j[key][k].get<double>();
  return v;
}

bool supported(const json& c) {
  return c.is_object() && c.value("supported", false);
}

std::string interval(std::size_t k, std::size_t n) {
  const stats::Proportion p = stats::wilson(k, n);
  return fmt::format("{}/{} = {:.2f} [{:.2f}, {:.2f}]", k, n, p.rate, p.lo, p.hi);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 || std::string(argv[1]) == "--help") {
    std::cerr << "usage: detection_summary DIR  (NAME.truth.json + NAME.diagnose.json pairs)\n";
    return 2;
  }
  const fs::path dir(argv[1]);
  if (!fs::is_directory(dir)) {
    std::cerr << "detection_summary: " << dir << " is not a directory\n";
    return 2;
  }
  using Key = std::tuple<std::string, double, std::size_t, std::string>;
  std::map<Key, Cell> cells;
  const std::string suffix = ".truth.json";
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= suffix.size() || name.substr(name.size() - suffix.size()) != suffix)
      continue;
    const std::string stem = name.substr(0, name.size() - suffix.size());
    const fs::path diag = dir / (stem + ".diagnose.json");
    if (!fs::exists(diag)) continue;
    json t, d;
    try {
      t = json::parse(std::ifstream(entry.path()));
      d = json::parse(std::ifstream(diag));
    } catch (const std::exception& e) {
      std::cerr << "detection_summary: skipping " << stem << ": " << e.what() << "\n";
      continue;
    }
    if (!t.contains("family") || !d.contains("ranking")) {
      std::cerr << "detection_summary: skipping " << stem << ": not a truth / diagnosis pair\n";
      continue;
    }
    const std::string fam_name = t["family"];
    const truth::Family fam = truth::family_from_name(fam_name);
    Cell& c = cells[{fam_name, t.value("strength", 0.0), t.value("n", std::size_t{0}),
                     t.value("design", std::string("?"))}];
    ++c.sets;
    const json& ranking = d["ranking"];
    const bool top = !ranking.empty() && supported(ranking[0]);
    bool any = false;
    for (const auto& r : ranking) any = any || supported(r);
    c.any += any;
    const std::string top_effect = top ? ranking[0].value("effect", "") : "";
    c.right += top && truth::names_family(fam, top_effect);
    if (top) {
      // A pair counts under the family of its first effect that maps to one.
      std::string f = "other";
      for (std::size_t a = 0, b; a <= top_effect.size(); a = b + 1) {
        b = top_effect.find('+', a);
        if (b == std::string::npos) b = top_effect.size();
        const std::string g = truth::candidate_family(top_effect.substr(a, b - a));
        if (g != "other") {
          f = g;
          break;
        }
      }
      ++c.found[f];
    }
    const std::string verdict = d.value("verdict", "?");
    ++c.verdicts[verdict];
    // The verdict agrees with the ranking (docs/diagnosis.md, "Verdict"): missing physics
    // exactly when the top candidate is supported or Holm-significant trends remain.
    const bool unnamed = d.contains("unnamed_structure") && !d["unnamed_structure"].empty();
    c.consistent += (verdict == "missing physics") == (top || unnamed);
    const auto mean = vec3(t, "mean_shift"), rms = vec3(t, "rms_shift"),
               res = vec3(t, "residual_rms_after_refit");
    for (int k = 0; k < 3; ++k) {
      c.mean[k] += mean[k];
      c.rms[k] += rms[k];
      c.residual[k] += res[k];
    }
    c.lab_units += t.value("shift_in_lab_units", 0.0);
    if (t.contains("oracle") && t["oracle"].is_object()) {
      const json& o = t["oracle"];
      const double z = o.value("z", 0.0);
      const auto size = o.value("family_size", truth::kOracleFamilySize);
      ++c.oracle_sets;
      c.oracle_z += z;
      c.oracle_single += truth::oracle_power(z, truth::kOracleAlpha);
      c.oracle_family += truth::oracle_power(
          z, truth::kOracleAlpha / static_cast<double>(std::max<std::size_t>(size, 1)));
    }
    c.seconds += d.value("seconds", 0.0);
    const fs::path ladder = dir / (stem + ".ladder.json");
    if (fs::exists(ladder)) {
      try {
        const json l = json::parse(std::ifstream(ladder));
        ++c.ladders;
        const auto& rungs = l["rungs"];
        if (rungs.size() >= 3) {
          const std::string a = rungs[1].value("added", ""), b = rungs[2].value("added", "");
          const auto expected = truth::expected_families(fam);
          const std::string fa = truth::candidate_family(a), fb = truth::candidate_family(b);
          c.both += expected.size() == 2 && fa != fb &&
                    std::find(expected.begin(), expected.end(), fa) != expected.end() &&
                    std::find(expected.begin(), expected.end(), fb) != expected.end();
        }
      } catch (const std::exception& e) {
        std::cerr << "detection_summary: " << ladder << ": " << e.what() << "\n";
      }
    }
  }
  if (cells.empty()) {
    std::cerr << "detection_summary: no NAME.truth.json with its NAME.diagnose.json in " << dir
              << "\n";
    return 1;
  }
  json out = {{"cells", json::array()}};
  std::cout
      << "| family | strength | n | design | sets | detected: right family first and supported "
         "(Wilson 95 %) | anything supported (Wilson 95 %) | top supported was | mean V_out "
         "shift (m/s, m/s, rad/s) | RMS shift | RMS left after refit | mean shift / lab scale | "
         "oracle z | oracle power, one hypothesis | oracle power, family | verdicts | verdict "
         "agrees with ranking | both found (ladder) | s per diagnosis |\n"
         "| :-- | --: | --: | :-- | --: | :-- | :-- | :-- | :-- | :-- | :-- | --: | --: | --: | "
         "--: | :-- | --: | :-- | --: |\n";
  std::size_t null_sets = 0, null_alarms = 0;
  for (const auto& [key, c] : cells) {
    const auto& [fam, strength, n, design] = key;
    const double N = static_cast<double>(c.sets);
    std::string verdicts, found;
    for (const auto& [v, k] : c.verdicts)
      verdicts += fmt::format("{}{} {}", verdicts.empty() ? "" : ", ", v, k);
    for (const auto& [f, k] : c.found)
      found += fmt::format("{}{} {}", found.empty() ? "" : ", ", f, k);
    if (fam == "none") null_sets += c.sets, null_alarms += c.any;
    const std::string both = c.ladders ? interval(c.both, c.ladders) : "";
    const double O = static_cast<double>(c.oracle_sets);
    auto oracle_cell = [&](double sum, const char* format) {
      return c.oracle_sets ? fmt::format(fmt::runtime(format), sum / O) : std::string("-");
    };
    auto oracle_json = [&](double sum) { return c.oracle_sets ? json(sum / O) : json(nullptr); };
    std::cout << fmt::format(
        "| {} | {:g} | {} | {} | {} | {} | {} | {} | {:.3f}, {:.3f}, {:.2f} | {:.3f}, {:.3f}, "
        "{:.2f} | {:.3f}, {:.3f}, {:.2f} | {:.2f} | {} | {} | {} | {} | {}/{} | {} | {:.1f} |\n",
        fam, strength, n, design, c.sets, fam == "none" ? "-" : interval(c.right, c.sets),
        interval(c.any, c.sets), found.empty() ? "-" : found, c.mean[0] / N, c.mean[1] / N,
        c.mean[2] / N, c.rms[0] / N, c.rms[1] / N, c.rms[2] / N, c.residual[0] / N,
        c.residual[1] / N, c.residual[2] / N, c.lab_units / N, oracle_cell(c.oracle_z, "{:.2f}"),
        oracle_cell(c.oracle_single, "{:.3f}"), oracle_cell(c.oracle_family, "{:.3f}"), verdicts,
        c.consistent, c.sets, both.empty() ? "-" : both, c.seconds / N);
    const stats::Proportion r = stats::wilson(c.right, c.sets), a = stats::wilson(c.any, c.sets);
    json cell = {
        {"family", fam},
        {"strength", strength},
        {"n", n},
        {"design", design},
        {"sets", c.sets},
        {"detected", c.right},
        {"detection_rate", r.rate},
        {"detection_wilson95", {r.lo, r.hi}},
        {"any_supported", c.any},
        {"any_supported_rate", a.rate},
        {"any_supported_wilson95", {a.lo, a.hi}},
        {"top_supported_family", c.found},
        {"mean_shift", {c.mean[0] / N, c.mean[1] / N, c.mean[2] / N}},
        {"rms_shift", {c.rms[0] / N, c.rms[1] / N, c.rms[2] / N}},
        {"residual_rms_after_refit", {c.residual[0] / N, c.residual[1] / N, c.residual[2] / N}},
        {"shift_in_lab_units", c.lab_units / N},
        {"oracle_z", oracle_json(c.oracle_z)},
        {"oracle_power_single", oracle_json(c.oracle_single)},
        {"oracle_power_family", oracle_json(c.oracle_family)},
        {"verdicts", c.verdicts},
        {"verdict_agrees_with_ranking", c.consistent},
        {"seconds_per_diagnosis", c.seconds / N}};
    if (c.ladders) cell["ladder"] = {{"sets", c.ladders}, {"both_found", c.both}};
    out["cells"].push_back(cell);
  }
  if (null_sets) {
    const stats::Proportion p = stats::wilson(null_alarms, null_sets);
    std::cout << fmt::format(
        "\nFalse alarms (null sets with anything supported): {}/{} = {:.3f}, Wilson 95 % "
        "interval [{:.3f}, {:.3f}] (upper bound {:.3f}).\n",
        null_alarms, null_sets, p.rate, p.lo, p.hi, p.hi);
    out["false_alarms"] = {{"null_sets", null_sets},
                           {"any_supported", null_alarms},
                           {"rate", p.rate},
                           {"wilson95", {p.lo, p.hi}},
                           {"upper_bound", p.hi}};
  }
  std::ofstream(dir / "summary.json") << out.dump(1) << "\n";
  return 0;
}
