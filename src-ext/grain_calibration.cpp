#include "grain_calibration.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <openturns/OT.hxx>
#include <openturns/TBB.hxx>
#include <optional>
#include <set>

#include "campaign_store.hpp"
#include "common/clock.hpp"
#include "common/error.hpp"
#include "fit/design.hpp"
#include "grain_packing.hpp"
#include "grain_surrogate.hpp"
#include "rebound_region.hpp"
#include "upscale.hpp"

namespace ricochet::dem {

namespace {

// One kriging model per V_out component, on inputs scaled to [0, 1].
struct Surrogate {
  std::vector<OT::KrigingResult> models;
  std::optional<OT::KrigingResult> packing;  ///< solid fraction, when the packing is asked for
  std::optional<OT::KrigingResult> rebound;  ///< rebound indicator (rebound_region.hpp)
  Vel3 predict_mean(const OT::Point& u) const {
    Vel3 m{};
    for (int c = 0; c < 3; ++c) m[c] = models[c].getMetaModel()(u)[0];
    return m;
  }
};

// The surrogate's inputs: given, or every grain parameter that the campaign varies (the bed's
// seed aside), each with its deck default.
void choose_inputs(GrainCalibrationResult& r, const ImpactSet& set,
                   const std::map<std::string, std::map<std::string, std::string>>& grain,
                   const Decks& decks, const GrainCalibrationOptions& options) {
  const std::string& campaign_h5 = r.source;
  r.parameters = options.parameters;
  if (r.parameters.empty()) {
    std::map<std::string, std::set<std::string>> values;
    for (const auto& im : set.impacts)
      if (const auto it = grain.find(im.id); it != grain.end())
        for (const auto& [k, v] : it->second) values[k].insert(v);
    for (const auto& [k, v] : values)
      if (v.size() > 1 && k != "bed.seed") r.parameters.push_back(k);
  }
  if (r.parameters.empty())
    throw InputError(campaign_h5, 0, "/dem/index/params",
                     "the campaign varies no grain parameter: nothing to calibrate");
  for (const auto& p : r.parameters) {
    const auto dot = p.find('.');
    const std::string section = p.substr(0, dot),
                      name = dot == std::string::npos ? "" : p.substr(dot + 1);
    const auto& list = section == "bed" ? decks.bed_params : decks.block_params;
    const auto it =
        std::find_if(list.begin(), list.end(), [&](const DeckParam& q) { return q.name == name; });
    if ((section != "bed" && section != "block") || it == list.end())
      throw InputError(campaign_h5, 0, p, "unknown grain parameter (use bed.NAME or block.NAME)");
    r.deck_default.push_back(grain_value(it->default_value, "<decks>", p));
  }
}

// Design points (replicas share every surrogate input) with their replica means, the pooled
// within-point sd, and the sampled box. Returns the mean number of replicas per point.
double gather_points(GrainCalibrationResult& r, const ImpactSet& set,
                     const std::map<std::string, std::map<std::string, std::string>>& grain) {
  const std::string& campaign_h5 = r.source;
  const std::size_t d = r.parameters.size();
  std::map<std::vector<double>, std::size_t> index;
  std::vector<std::array<std::vector<double>, 3>> samples;
  for (const auto& im : set.impacts) {
    const auto it = grain.find(im.id);
    if (it == grain.end()) continue;
    std::vector<double> x;
    for (const auto& p : r.parameters) x.push_back(grain_value(it->second.at(p), campaign_h5, p));
    auto [pos, inserted] = index.emplace(x, r.points.size());
    if (inserted) {
      r.points.emplace_back().x = x;
      samples.emplace_back();
    }
    auto& pt = r.points[pos->second];
    pt.ids.push_back(im.id);
    ++pt.replicas;
    for (int c = 0; c < 3; ++c) samples[pos->second][c].push_back(im.vout[c]);
  }
  const std::size_t n = r.points.size();
  if (n < d + 2)
    throw InputError(
        campaign_h5, 0, "/impacts",
        fmt::format("{} design points with a rebound for {} parameters: need at least {}", n, d,
                    d + 2));
  // Replica means and the pooled within-point variance (the noise of a mean: var / replicas).
  Vel3 ss{}, dof{};
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const auto& v = samples[i][c];
      double m = 0;
      for (double x : v) m += x;
      m /= static_cast<double>(v.size());
      r.points[i].mean[c] = m;
      for (double x : v) ss[c] += (x - m) * (x - m);
      dof[c] += static_cast<double>(v.size()) - 1;
    }
  for (int c = 0; c < 3; ++c) r.replicate_sd[c] = dof[c] > 0 ? std::sqrt(ss[c] / dof[c]) : 0.0;
  double mean_replicas = 0;
  for (const auto& p : r.points)
    mean_replicas += static_cast<double>(p.replicas) / static_cast<double>(n);
  r.lower.assign(d, 0.0);
  r.upper.assign(d, 0.0);
  for (std::size_t k = 0; k < d; ++k) {
    r.lower[k] = r.upper[k] = r.points[0].x[k];
    for (const auto& p : r.points) {
      r.lower[k] = std::min(r.lower[k], p.x[k]);
      r.upper[k] = std::max(r.upper[k], p.x[k]);
    }
    if (!(r.upper[k] > r.lower[k]))
      throw InputError(campaign_h5, 0, r.parameters[k], "takes one value only among the rebounds");
  }
  return mean_replicas;
}

// The target: the measured rebounds' mean and standard deviation.
void target_moments(GrainCalibrationResult& r, const ImpactSet& target) {
  r.target_n = target.impacts.size();
  for (int c = 0; c < 3; ++c) {
    double m = 0, s = 0;
    for (const auto& im : target.impacts) m += im.vout[c];
    m /= static_cast<double>(r.target_n);
    for (const auto& im : target.impacts) s += (im.vout[c] - m) * (im.vout[c] - m);
    r.target_mean[c] = m;
    r.target_sd[c] = std::sqrt(s / static_cast<double>(r.target_n - 1));
  }
}

// One kriging model per component on the scaled inputs u, with the replicas' noise, and its
// leave-one-out check.
Surrogate fit_surrogate(GrainCalibrationResult& r, const OT::Sample& u, double mean_replicas) {
  const std::size_t n = r.points.size();
  Surrogate sur;
  for (int c = 0; c < 3; ++c) {
    OT::Sample y(n, 1);
    for (std::size_t i = 0; i < n; ++i) y(i, 0) = r.points[i].mean[c];
    const double noise = r.replicate_sd[c] * r.replicate_sd[c] / mean_replicas;
    sur.models.push_back(fit_kriging(u, y, noise, nullptr));
    std::vector<double> loo;
    const auto [q2, rmse] = leave_one_out(u, y, noise, sur.models.back().getCovarianceModel(), loo);
    for (std::size_t i = 0; i < n; ++i) r.points[i].loo[c] = loo[i];
    r.q2[c] = q2;
    r.rmse_loo[c] = rmse;
  }
  return sur;
}

// Sobol indices on the surrogate (Saltelli 2010 estimators, OpenTURNS), inputs uniform on the
// sampled box, with bootstrap intervals.
void sobol_on_surrogate(GrainCalibrationResult& r, const Surrogate& sur, std::size_t sobol_n) {
  const std::size_t d = r.parameters.size();
  const OT::ComposedDistribution unit(
      OT::ComposedDistribution::DistributionCollection(d, OT::Uniform(0.0, 1.0)));
  const OT::Sample sobol_in = OT::SobolIndicesExperiment(unit, sobol_n).generate();
  for (int c = 0; c < 3; ++c) {
    OT::SaltelliSensitivityAlgorithm algo(sobol_in, sur.models[c].getMetaModel()(sobol_in),
                                          sobol_n);
    algo.setBootstrapSize(200);
    const OT::Point f = algo.getFirstOrderIndices(), t = algo.getTotalOrderIndices();
    const OT::Interval fi = algo.getFirstOrderIndicesInterval(),
                       ti = algo.getTotalOrderIndicesInterval();
    for (std::size_t k = 0; k < d; ++k) {
      r.first[c].push_back(f[k]);
      r.total[c].push_back(t[k]);
      r.first_lo[c].push_back(fi.getLowerBound()[k]);
      r.first_hi[c].push_back(fi.getUpperBound()[k]);
      r.total_lo[c].push_back(ti.getLowerBound()[k]);
      r.total_hi[c].push_back(ti.getUpperBound()[k]);
    }
  }
}

// The calibrated point: the smallest expected misfit J over a space-filling search (search_u),
// then a second search in a box a tenth as wide around the best candidate (local: a unit
// design, moved there). Returns the best point in unit coordinates.
OT::Point search_best(GrainCalibrationResult& r, const Surrogate& sur,
                      const std::vector<double>& search_u, std::vector<double> local,
                      std::size_t search_n) {
  const std::size_t d = r.parameters.size();
  // Outside the solid-fraction band (with one) a point is not a sand-like bed, and outside the
  // rebound region (with one) its bed is not expected to give a rebound at all: J = +inf there.
  const bool banded = sur.packing && r.solid_fraction_band.size() == 2;
  std::size_t in_region = 0;
  auto misfit = [&](const OT::Sample& s, std::vector<double>& j, std::vector<char>* ok) {
    j.assign(s.getSize(), 0.0);
    if (ok) ok->assign(s.getSize(), 1);
    if (banded) {
      const OT::Sample phi = sur.packing->getMetaModel()(s);
      for (std::size_t i = 0; i < s.getSize(); ++i)
        if (phi(i, 0) < r.solid_fraction_band[0] || phi(i, 0) > r.solid_fraction_band[1])
          j[i] = std::numeric_limits<double>::infinity();
    }
    if (sur.rebound) {
      const OT::Sample p = sur.rebound->getMetaModel()(s);
      for (std::size_t i = 0; i < s.getSize(); ++i) {
        if (p(i, 0) < r.rebound_threshold)
          j[i] = std::numeric_limits<double>::infinity();
        else if (ok)
          ++in_region;
      }
    }
    for (int c = 0; c < 3; ++c) {
      const OT::Sample m = sur.models[c].getMetaModel()(s);
      const OT::Sample v = sur.models[c].getConditionalMarginalVariance(s);
      const double sd2 = r.target_sd[c] * r.target_sd[c];
      for (std::size_t i = 0; i < s.getSize(); ++i) {
        const double e = m(i, 0) - r.target_mean[c];
        j[i] += (e * e + std::max(0.0, v(i, 0))) / sd2;
        if (ok && std::abs(e) > 0.5 * r.target_sd[c]) (*ok)[i] = 0;
      }
    }
  };
  auto to_sample = [&](const std::vector<double>& flat, std::size_t count) {
    OT::Sample s(count, d);
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t k = 0; k < d; ++k) s(i, k) = flat[i * d + k];
    return s;
  };
  const OT::Sample search = to_sample(search_u, search_n);
  std::vector<double> j;
  std::vector<char> ok;
  misfit(search, j, &ok);
  std::size_t best = static_cast<std::size_t>(std::min_element(j.begin(), j.end()) - j.begin());
  r.acceptable_fraction =
      static_cast<double>(std::count(ok.begin(), ok.end(), 1)) / static_cast<double>(ok.size());
  const auto admissible = static_cast<std::size_t>(
      std::count_if(j.begin(), j.end(), [](double v) { return std::isfinite(v); }));
  r.admissible_fraction = static_cast<double>(admissible) / static_cast<double>(j.size());
  if (sur.rebound)
    r.rebound_box_fraction = static_cast<double>(in_region) / static_cast<double>(j.size());
  if (admissible == 0) {
    std::string why;
    if (banded) {
      const auto [lo, hi] = solid_fraction_range(r);
      why = fmt::format(
          "a predicted solid fraction in [{:.3f}, {:.3f}] (the design's beds span "
          "[{:.3f}, {:.3f}])",
          r.solid_fraction_band[0], r.solid_fraction_band[1], lo, hi);
    }
    if (sur.rebound)
      why += fmt::format(
          "{}a predicted rebound probability of at least {} ({:.1f} % of the box "
          "has it)",
          why.empty() ? "" : " and ", r.rebound_threshold, 100 * r.rebound_box_fraction);
    throw InputError(r.source, 0, banded ? "--solid-fraction" : "--rebound-threshold",
                     "no point of the sampled box has " + why);
  }
  OT::Point ubest = search[best];
  double jbest = j[best];
  for (std::size_t i = 0; i < search_n / 4; ++i)
    for (std::size_t k = 0; k < d; ++k)
      local[i * d + k] = std::clamp(ubest[k] + 0.1 * (local[i * d + k] - 0.5), 0.0, 1.0);
  const OT::Sample near = to_sample(local, search_n / 4);
  misfit(near, j, nullptr);
  best = static_cast<std::size_t>(std::min_element(j.begin(), j.end()) - j.begin());
  if (j[best] < jbest) {
    ubest = near[best];
    jbest = j[best];
  }
  r.best_misfit = jbest;
  for (std::size_t k = 0; k < d; ++k)
    r.best.push_back(r.lower[k] + ubest[k] * (r.upper[k] - r.lower[k]));
  for (int c = 0; c < 3; ++c) {
    r.best_mean[c] = sur.models[c].getMetaModel()(ubest)[0];
    r.best_sd[c] = std::sqrt(std::max(0.0, sur.models[c].getConditionalMarginalVariance(ubest)));
  }
  if (sur.rebound) r.best_rebound = sur.rebound->getMetaModel()(ubest)[0];
  if (sur.packing) {
    r.best_solid_fraction = sur.packing->getMetaModel()(ubest)[0];
    r.best_solid_fraction_sd =
        std::sqrt(std::max(0.0, sur.packing->getConditionalMarginalVariance(ubest)));
  }
  return ubest;
}

// The abacus: one parameter at a time through the calibrated point (unit coordinates ubest).
void abacus(GrainCalibrationResult& r, const Surrogate& sur, const OT::Point& ubest) {
  const std::size_t d = r.parameters.size(), grid_n = 41;
  r.grid.resize(d);
  r.curve_mean.resize(d);
  r.curve_sd.resize(d);
  if (sur.rebound) r.curve_rebound.resize(d);
  for (std::size_t k = 0; k < d; ++k) {
    OT::Sample s(grid_n, d);
    for (std::size_t i = 0; i < grid_n; ++i) {
      s[i] = ubest;
      s(i, k) = static_cast<double>(i) / static_cast<double>(grid_n - 1);
      r.grid[k].push_back(r.lower[k] + s(i, k) * (r.upper[k] - r.lower[k]));
    }
    for (int c = 0; c < 3; ++c) {
      const OT::Sample m = sur.models[c].getMetaModel()(s);
      const OT::Sample v = sur.models[c].getConditionalMarginalVariance(s);
      for (std::size_t i = 0; i < grid_n; ++i) {
        r.curve_mean[k][c].push_back(m(i, 0));
        r.curve_sd[k][c].push_back(std::sqrt(std::max(0.0, v(i, 0))));
      }
    }
    if (sur.rebound) {
      const OT::Sample p = sur.rebound->getMetaModel()(s);
      for (std::size_t i = 0; i < grid_n; ++i) r.curve_rebound[k].push_back(p(i, 0));
    }
  }
}

}  // namespace

GrainCalibrationResult calibrate_grains(const std::string& campaign_h5, const Decks& decks,
                                        const ImpactSet& target,
                                        const GrainCalibrationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  GrainCalibrationResult r;
  r.source = campaign_h5;
  if (target.impacts.size() < 2)
    throw InputError(target.source, 0, "vout", "the target needs at least 2 impacts");
  ImpactSet set = read_impact_set_h5(campaign_h5);
  set = filter_nonempty(set, options.where, campaign_h5);
  const auto index = read_campaign_index(campaign_h5);
  for (const auto& e : index)
    if (e.status != "rebound") ++r.failed;
  if (!(options.rebound_threshold >= 0 && options.rebound_threshold < 1))
    throw InputError("<command line>", 0, "--rebound-threshold",
                     fmt::format("{} is outside [0, 1)", options.rebound_threshold));
  if (!options.solid_fraction.empty()) {
    const auto& b = options.solid_fraction;
    if (b.size() != 2 || !(b[0] > 0 && b[0] < b[1] && b[1] < 1))
      throw InputError("<command line>", 0, "--solid-fraction",
                       "expects LO,HI with 0 < LO < HI < 1");
    r.solid_fraction_band = b;
  }
  const auto grain = campaign_grain_parameters(campaign_h5, index, decks);
  choose_inputs(r, set, grain, decks, options);
  const double mean_replicas = gather_points(r, set, grain);
  tally_rebounds(r, index, grain);
  // The packing: asked for by any of the three options. Each bed's comes from the file's record,
  // else the cache, else its grain count, so the cache is needed only for a bed that is neither
  // recorded nor counted (measure_points_packing says which).
  const bool packing = !options.bed_cache.empty() || options.packing_from_grain_count ||
                       !options.solid_fraction.empty();
  if (packing)
    measure_points_packing(r, campaign_h5, index, options.bed_cache,
                           options.packing_from_grain_count, grain);
  const std::size_t n = r.points.size(), d = r.parameters.size();
  OT::Sample u(n, d);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < d; ++k)
      u(i, k) = (r.points[i].x[k] - r.lower[k]) / (r.upper[k] - r.lower[k]);
  target_moments(r, target);

  // The search designs first: lhs_unit_design takes the OpenTURNS generator's lock itself.
  const auto search_u = fit::lhs_unit_design(d, options.search_n, options.seed + 1);
  const auto local = fit::lhs_unit_design(d, options.search_n / 4, options.seed + 2);
  // OpenTURNS's random generator is process-wide (fit/design.hpp): hold it for the whole fit.
  std::lock_guard<std::mutex> lock(fit::openturns_rng_mutex());
  // OpenTURNS warns whenever it narrows the kriging scale bounds to the data's range ("for
  // coherency"): noise for the user, the bounds are ours. Warnings off while this fit runs.
  struct QuietWarnings {
    OT::Log::Severity flags = OT::Log::Flags();
    QuietWarnings() { OT::Log::Show(flags & ~OT::Log::WARN); }
    ~QuietWarnings() { OT::Log::Show(flags); }
  } quiet;
  // OpenTURNS splits the kriging's evaluations over TBB threads, whose reductions sum in a
  // scheduling-dependent order: the same command gave results differing in the last digits from
  // run to run. One thread while this fit runs keeps a calibration reproducible bit for bit.
  struct OneThread {
    OT::UnsignedInteger threads = OT::TBB::GetThreadsNumber();
    OneThread() { OT::TBB::SetThreadsNumber(1); }
    ~OneThread() { OT::TBB::SetThreadsNumber(threads); }
  } one_thread;
  OT::RandomGenerator::SetSeed(options.seed);
  Surrogate sur = fit_surrogate(r, u, mean_replicas);
  if (packing) sur.packing = fit_packing(r, u);
  if (options.rebound_threshold > 0) {
    sur.rebound = fit_rebound_region(r);
    if (sur.rebound) r.rebound_threshold = options.rebound_threshold;
  }
  sobol_on_surrogate(r, sur, options.sobol_n);
  const OT::Point ubest = search_best(r, sur, search_u, local, options.search_n);
  abacus(r, sur, ubest);
  r.seconds = seconds_since(start);
  return r;
}

std::array<double, 2> solid_fraction_range(const GrainCalibrationResult& r) {
  std::array<double, 2> range = {NAN, NAN};
  for (const auto& p : r.points)
    if (std::isfinite(p.solid_fraction)) {
      range[0] = std::isnan(range[0]) ? p.solid_fraction : std::min(range[0], p.solid_fraction);
      range[1] = std::isnan(range[1]) ? p.solid_fraction : std::max(range[1], p.solid_fraction);
    }
  return range;
}

}  // namespace ricochet::dem
