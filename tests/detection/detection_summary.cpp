// `detection_summary DIR`: the detection benchmark's table (docs/detection-benchmark.md) from the
// pairs NAME.truth.json (independent_truth --truth) and NAME.diagnose.json (ricochet diagnose
// --json) in DIR. Per cell (family, strength, n, design): how often the right family is the top
// SUPPORTED candidate (truth_sim.hpp, names_family), how often anything is supported, with
// Wilson 95 % intervals (stats::wilson), the verdicts, and the effect size in physical units.
// Writes the markdown table on stdout and DIR/summary.json.
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

struct Cell {
  std::size_t sets = 0, right = 0, any = 0, consistent = 0;
  std::map<std::string, std::size_t> verdicts;
  std::array<double, 3> shift{};
  double lab_units = 0, seconds = 0;
};

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: detection_summary DIR\n";
    return 2;
  }
  const fs::path dir(argv[1]);
  using Key = std::tuple<std::string, double, std::size_t, std::string>;
  std::map<Key, Cell> cells;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    const std::string suffix = ".truth.json";
    if (name.size() <= suffix.size() || name.substr(name.size() - suffix.size()) != suffix)
      continue;
    const fs::path diag = dir / (name.substr(0, name.size() - suffix.size()) + ".diagnose.json");
    if (!fs::exists(diag)) continue;
    nlohmann::json t, d;
    try {
      t = nlohmann::json::parse(std::ifstream(entry.path()));
      d = nlohmann::json::parse(std::ifstream(diag));
    } catch (const std::exception& e) {
      std::cerr << "detection_summary: skipping " << name << ": " << e.what() << "\n";
      continue;
    }
    const truth::Family fam = truth::family_from_name(t["family"]);
    Cell& c = cells[{t["family"], t["strength"], t["n"], t["design"]}];
    ++c.sets;
    const auto& ranking = d["ranking"];
    const bool top_supported = !ranking.empty() && ranking[0]["supported"].get<bool>();
    bool any = false;
    for (const auto& r : ranking) any = any || r["supported"].get<bool>();
    c.any += any;
    c.right += top_supported && truth::names_family(fam, ranking[0]["effect"]);
    const std::string verdict = d["verdict"];
    ++c.verdicts[verdict];
    // The verdict never contradicts the ranking: a supported top candidate means missing
    // physics; missing physics without one needs a Holm-significant trend.
    const bool unnamed = !d["unnamed_structure"].empty();
    c.consistent += (!top_supported || verdict == "missing physics") &&
                    (verdict != "missing physics" || top_supported || unnamed);
    for (int k = 0; k < 3; ++k) c.shift[k] += t["mean_shift"][k].get<double>();
    c.lab_units += t["shift_in_lab_units"].get<double>();
    c.seconds += d["seconds"].get<double>();
  }
  nlohmann::json out = nlohmann::json::array();
  std::cout << "| family | strength | n | design | sets | right family first & supported "
               "(Wilson 95 %) | anything supported (Wilson 95 %) | mean V_out shift (m/s, m/s, "
               "rad/s) | shift / lab scale | verdicts | verdict agrees with ranking | s per set |\n"
               "| :-- | --: | --: | :-- | --: | :-- | :-- | :-- | --: | :-- | --: | --: |\n";
  for (const auto& [key, c] : cells) {
    const auto& [fam, strength, n, design] = key;
    const double N = static_cast<double>(c.sets);
    const stats::Proportion r = stats::wilson(c.right, c.sets), a = stats::wilson(c.any, c.sets);
    std::string verdicts;
    for (const auto& [v, k] : c.verdicts)
      verdicts += fmt::format("{}{} {}", verdicts.empty() ? "" : ", ", v, k);
    std::cout << fmt::format(
        "| {} | {:g} | {} | {} | {} | {}/{} = {:.2f} [{:.2f}, {:.2f}] | {}/{} = {:.2f} [{:.2f}, "
        "{:.2f}] | {:.3f}, {:.3f}, {:.2f} | {:.2f} | {} | {}/{} | {:.1f} |\n",
        fam, strength, n, design, c.sets, c.right, c.sets, r.rate, r.lo, r.hi, c.any, c.sets,
        a.rate, a.lo, a.hi, c.shift[0] / N, c.shift[1] / N, c.shift[2] / N, c.lab_units / N,
        verdicts, c.consistent, c.sets, c.seconds / N);
    out.push_back({{"family", fam},
                   {"strength", strength},
                   {"n", n},
                   {"design", design},
                   {"sets", c.sets},
                   {"right", c.right},
                   {"right_wilson", {r.lo, r.hi}},
                   {"any_supported", c.any},
                   {"any_wilson", {a.lo, a.hi}},
                   {"mean_shift", {c.shift[0] / N, c.shift[1] / N, c.shift[2] / N}},
                   {"shift_in_lab_units", c.lab_units / N},
                   {"verdicts", c.verdicts},
                   {"consistent", c.consistent},
                   {"seconds_per_set", c.seconds / N}});
  }
  std::ofstream(dir / "summary.json") << out.dump(1) << "\n";
  return 0;
}
