// Paired comparison of two conditions of the same impacts (paired.hpp).
#include "stats/paired.hpp"
#include "common/nan.hpp"

#include <fmt/format.h>
#include <openturns/DistFunc.hxx>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "stats/stats.hpp"
#include "stats/table2.hpp"

namespace ricochet::stats {
namespace {

PairedComponent component(const std::vector<double>& d, const PairedOptions& o) {
  PairedComponent c;
  const Summary s = summarize(d);
  c.n = s.n;
  c.mean = s.mean;
  c.sd = c.lo = c.hi = kNaN;
  if (s.n >= 2) {
    c.sd = s.std;
    // Student t interval of the mean (the pairs are independent: one bed seed and state each).
    const double t =
        OT::DistFunc::qStudent(static_cast<double>(s.n - 1), 0.5 * (1.0 + o.level), false);
    const double half = t * s.std / std::sqrt(static_cast<double>(s.n));
    c.lo = s.mean - half;
    c.hi = s.mean + half;
    c.interval_holds_zero = c.lo <= 0 && c.hi >= 0;
    c.within_margin = std::abs(s.mean) < o.margin;
    c.holds = c.interval_holds_zero || c.within_margin;
  }
  return c;
}

}  // namespace

OptionProblems PairedOptions::problems() const {
  OptionProblems p;
  check_range(p, "level", level, kLevel);
  check_range(p, "margin", margin, kMargin);
  return p;
}

std::array<double, 3> vout_std(const ImpactSet& set) {
  if (set.empty()) throw InputError(set.source, 0, "shape", "no release to take a scale from");
  const Table2 t = table2(set, set.source, "");
  return {t.columns[1].std, t.columns[3].std, t.columns[5].std};  // kTable2Columns' V_out
}

PairedComparison paired_comparison(const ImpactSet& set, const std::string& base,
                                   const std::string& other,
                                   const std::map<std::string, std::array<double, 3>>& scale,
                                   const PairedOptions& options) {
  require_valid(options.problems(), "stats::paired_comparison");
  if (base.empty() || other.empty() || base == other)
    throw std::invalid_argument("paired_comparison: two different, non-empty prefixes");
  PairedComparison out;
  out.base = base;
  out.other = other;
  out.options = options;
  out.scales = scale;
  // An id belongs to the condition of the longest prefix it starts with ("E1" and "E10": "E10-x"
  // is E10's).
  const auto key_of = [](const std::string& id, const std::string& prefix) {
    return id.substr(prefix.size());
  };
  const auto is_base = [&](const std::string& id) {
    return id.starts_with(base) && !(id.starts_with(other) && other.size() > base.size());
  };
  const auto is_other = [&](const std::string& id) {
    return id.starts_with(other) && !(id.starts_with(base) && base.size() > other.size());
  };
  std::unordered_map<std::string, const Impact*> others;
  for (const Impact& im : set.impacts)
    if (is_other(im.id)) others.emplace(key_of(im.id, other), &im);
  std::unordered_set<std::string> used;
  std::array<std::vector<double>, 3> d;
  for (const Impact& im : set.impacts) {
    if (!is_base(im.id)) continue;
    const std::string key = key_of(im.id, base);
    const auto it = others.find(key);
    if (it == others.end()) {
      out.unpaired.push_back(im.id);
      continue;
    }
    used.insert(key);
    const Impact& b = *it->second;
    if (b.shape != im.shape)
      throw InputError(set.source, 0, "shape",
                       fmt::format("impacts '{}' ({}) and '{}' ({}) pair but differ in shape",
                                   im.id, im.shape, b.id, b.shape));
    const auto sc = scale.find(im.shape);
    if (sc == scale.end())
      throw InputError(set.source, 0, "shape",
                       fmt::format("no scale for shape '{}' (impacts '{}' and '{}'): give a lab "
                                   "set of that shape",
                                   im.shape, im.id, b.id));
    std::array<double, 3> diff{};
    for (std::size_t k = 0; k < 3; ++k) {
      if (!(sc->second[k] > 0))
        throw InputError(set.source, 0, "shape",
                         fmt::format("the scale of shape '{}' is not positive", im.shape));
      diff[k] = (b.vout[static_cast<int>(k)] - im.vout[static_cast<int>(k)]) / sc->second[k];
      d[k].push_back(diff[k]);
    }
    out.keys.push_back(key);
    out.shapes.push_back(im.shape);
    out.differences.push_back(diff);
  }
  for (const Impact& im : set.impacts)
    if (is_other(im.id) && !used.contains(key_of(im.id, other))) out.unpaired.push_back(im.id);
  if (out.keys.empty())
    throw InputError(set.source, 0, "id",
                     fmt::format("no pair of ids '{}KEY' and '{}KEY' in the set", base, other));
  out.all_hold = true;
  for (std::size_t k = 0; k < 3; ++k) {
    out.components[k] = component(d[k], options);
    out.all_hold = out.all_hold && out.components[k].holds;
  }
  return out;
}

namespace {

constexpr std::array<const char*, 3> kComponents = {"V_out^x", "V_out^y", "omega_out"};
constexpr std::array<const char*, 3> kKeys = {"vout_x", "vout_y", "wout"};

}  // namespace

nlohmann::json to_json(const PairedComparison& c) {
  // nlohmann::json writes NaN (no interval with fewer than 2 pairs) as null.
  nlohmann::json comps = nlohmann::json::object();
  for (std::size_t k = 0; k < 3; ++k) {
    const PairedComponent& x = c.components[k];
    comps[kKeys[k]] = {{"n", x.n},
                       {"mean", x.mean},
                       {"sd", x.sd},
                       {"interval", {x.lo, x.hi}},
                       {"interval_holds_zero", x.interval_holds_zero},
                       {"within_margin", x.within_margin},
                       {"holds", x.holds}};
  }
  nlohmann::json pairs = nlohmann::json::array();
  for (std::size_t i = 0; i < c.keys.size(); ++i)
    pairs.push_back(
        {{"key", c.keys[i]},
         {"shape", c.shapes[i]},
         {"difference", {c.differences[i][0], c.differences[i][1], c.differences[i][2]}}});
  nlohmann::json sc = nlohmann::json::object();
  for (const auto& [shape, s] : c.scales) sc[shape] = {s[0], s[1], s[2]};
  return {{"base", c.base},
          {"against", c.other},
          {"level", c.options.level},
          {"margin", c.options.margin},
          {"scales", sc},
          {"pairs", pairs},
          {"unpaired", c.unpaired},
          {"components", comps},
          {"all_hold", c.all_hold}};
}

void write_csv(const std::string& path, const PairedComparison& c, const std::string& data,
               const std::string& option) {
  CsvTable t;
  t.comment(
      fmt::format("ricochet paired {}: {} minus {}, in lab standard deviations of each "
                  "shape's V_out",
                  data, c.other, c.base));
  t.row({"key", "shape", "d_vout_x[sd]", "d_vout_y[sd]", "d_wout[sd]"});
  for (std::size_t i = 0; i < c.keys.size(); ++i)
    t.row({c.keys[i], c.shapes[i], CsvTable::num(c.differences[i][0]),
           CsvTable::num(c.differences[i][1]), CsvTable::num(c.differences[i][2])});
  t.write(path, option);
}

std::string format_text(const PairedComparison& c, const std::string& data) {
  std::string out = fmt::format(
      "{}: {} minus {}, {} pair{}; differences in lab standard deviations of each shape's "
      "V_out\n",
      data, c.other, c.base, c.keys.size(), c.keys.size() == 1 ? "" : "s");
  out += fmt::format("{:<10} {:>3} {:>8} {:>7}   {:<22} {}\n", "component", "n", "mean", "sd",
                     fmt::format("{:.0f} % interval", 100 * c.options.level), "holds");
  for (std::size_t k = 0; k < 3; ++k) {
    const PairedComponent& x = c.components[k];
    const std::string why = x.n < 2 ? "fewer than 2 pairs: no interval"
                            : x.interval_holds_zero && x.within_margin
                                ? "interval holds 0, |mean| < margin"
                            : x.interval_holds_zero ? "interval holds 0"
                            : x.within_margin       ? "|mean| < margin"
                                                    : "moves";
    out +=
        fmt::format("{:<10} {:>3} {:>+8.3f} {:>7.3f}   [{:+.3f}, {:+.3f}]{:>5} {} ({})\n",
                    kComponents[k], x.n, x.mean, x.sd, x.lo, x.hi, "", x.holds ? "yes" : "no", why);
  }
  out += fmt::format("all components hold (margin {} sd): {}\n", c.options.margin,
                     c.all_hold ? "yes" : "no");
  if (!c.unpaired.empty()) {
    std::string ids;
    for (const auto& id : c.unpaired) ids += (ids.empty() ? "" : ", ") + id;
    out += "unpaired: " + ids + "\n";
  }
  return out;
}

}  // namespace ricochet::stats
