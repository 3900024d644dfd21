// Paired comparison of two conditions of the same impacts (paired.hpp).
#include "stats/paired.hpp"

#include <fmt/format.h>
#include <openturns/DistFunc.hxx>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "common/error.hpp"
#include "stats/stats.hpp"

namespace ricochet::stats {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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

std::array<double, 3> vout_std(const ImpactSet& set) {
  if (set.empty()) throw InputError(set.source, 0, "shape", "no release to take a scale from");
  std::array<double, 3> out{};
  for (int k = 0; k < 3; ++k) {
    std::vector<double> x;
    for (const Impact& im : set.impacts) x.push_back(im.vout[k]);
    out[static_cast<std::size_t>(k)] = summarize(x).std;
  }
  return out;
}

PairedComparison paired_comparison(const ImpactSet& set, const std::string& base,
                                   const std::string& other,
                                   const std::map<std::string, std::array<double, 3>>& scale,
                                   const PairedOptions& options) {
  if (base.empty() || other.empty() || base == other)
    throw std::invalid_argument("paired_comparison: two different, non-empty prefixes");
  if (!(options.level > 0 && options.level < 1) || !(options.margin >= 0))
    throw std::invalid_argument("paired_comparison: level in (0, 1), margin >= 0");
  PairedComparison out;
  out.base = base;
  out.other = other;
  out.options = options;
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
  std::unordered_map<std::string, bool> used;
  std::array<std::vector<double>, 3> d;
  for (const Impact& im : set.impacts) {
    if (!is_base(im.id)) continue;
    const std::string key = key_of(im.id, base);
    const auto it = others.find(key);
    if (it == others.end()) {
      out.unpaired.push_back(im.id);
      continue;
    }
    used[key] = true;
    const Impact& b = *it->second;
    const auto sc = scale.find(im.shape);
    if (sc == scale.end() || b.shape != im.shape)
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
    if (is_other(im.id) && !used.count(key_of(im.id, other))) out.unpaired.push_back(im.id);
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

}  // namespace ricochet::stats
