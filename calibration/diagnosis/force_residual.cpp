// measured_history and force_residual (force_residual.hpp).
#include "diagnosis/force_residual.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "common/clock.hpp"
#include "common/error.hpp"
#include "common/nan.hpp"
#include "stats/robust.hpp"
#include "stats/track_summary.hpp"

namespace ricochet::diagnosis {

MeasuredHistory measured_history(const BlockTrack& in, const std::string& id, const Shape& shape,
                                 const std::string& source) {
  BlockTrack track = in;
  track.pad();
  const std::string field = std::string(kTracksGroup) + "/" + id;
  const std::size_t n = track.size();
  if (n < 2) throw InputError(source, 0, field, "a track needs at least two records");
  const auto all_finite = [&](const std::vector<double>& c) {
    return std::all_of(c.begin(), c.end(), [](double v) { return std::isfinite(v); });
  };
  if (!all_finite(track.fcx) || !all_finite(track.fcy))
    throw InputError(source, 0, field, "the contact force (fcx, fcy) is missing or not finite");

  MeasuredHistory h;
  h.id = id;
  h.source = source;
  double mass = track.block_mass_kg;
  if (!std::isfinite(mass)) mass = stats::free_flight_mass_kg(track);
  h.force_scale = std::isfinite(mass) && mass > 0 ? shape.mass_kg / mass : 1.0;

  std::vector<double> surface;
  for (std::size_t i = 0; i < n; ++i)
    if (std::isfinite(track.penetration[i]))
      surface.push_back(track.y[i] - shape.depth_below_centroid(track.theta[i]) +
                        track.penetration[i]);
  h.surface_m = surface.empty() ? 0.0 : stats::robust_summarize(surface).median;

  for (std::size_t i = 0; i < n; ++i) {
    h.path.push_back({track.t[i], track.x[i], track.y[i] - h.surface_m, track.theta[i], track.vx[i],
                      track.vy[i], track.w[i]});
    h.fx_N.push_back(h.force_scale * track.fcx[i]);
    h.fy_N.push_back(h.force_scale * track.fcy[i]);
    h.torque_Nm.push_back(h.force_scale * track.torque[i]);  // NaN when not recorded
    const double depth = shape.depth_below_centroid(track.theta[i]) - h.path.back().y_m;
    if (depth > 0 && std::isfinite(track.penetration[i]))
      h.geometry_mismatch_m =
          std::max(h.geometry_mismatch_m, std::abs(depth - track.penetration[i]));
  }
  return h;
}

ReleaseResidual force_residual(const MeasuredHistory& history, const Model& model,
                               const Shape& shape, std::span<const double> params,
                               const EngineOptions& engine) {
  std::vector<PathForce> law;
  try {
    law = law_force_along(model, shape, history.path, params, engine);
  } catch (const InputError& e) {
    if (history.source.empty() || e.file() != "<path>") throw;
    throw InputError(history.source, 0, std::string(kTracksGroup) + "/" + history.id,
                     fmt::format("record {}: {}", e.line(), e.detail()));
  }
  ReleaseResidual r;
  for (std::size_t i = 0; i < law.size(); ++i) {
    const PathForce& f = law[i];
    if (!(f.h_m > 0)) continue;
    const PathState& p = history.path[i];
    const double tx = f.ny, ty = -f.nx;  // the tangent t of the contact frame (effect.hpp)
    const double rx = history.fx_N[i] - f.fx_N, ry = history.fy_N[i] - f.fy_N;
    const double rt = history.torque_Nm[i] - f.torque_Nm;
    ContactSample s;
    s.h_m = f.h_m;
    s.vn_mps = f.vn_mps;
    s.vt_mps = f.vt_mps;
    s.vx_mps = p.vx_mps * tx + p.vy_mps * ty;
    s.omega_radps = p.w_radps;
    s.loading = f.loading;
    r.samples.push_back(s);
    r.t_s.push_back(p.t_s);
    // A force at the contact point (rcx, rcy) has the moment rcx fy - rcy fx about the centre:
    // what is left of the torque residual is a moment the force residual does not explain.
    r.residual.push_back(
        {rx * f.nx + ry * f.ny, rx * tx + ry * ty, rt - (f.rcx_m * ry - f.rcy_m * rx)});
  }
  return r;
}

std::vector<std::optional<MeasuredHistory>> measured_histories(const std::string& data,
                                                               const ImpactSet& set,
                                                               const Shape& shape) {
  const auto kept = block_track_ids(data);
  const std::set<std::string> have(kept.begin(), kept.end());
  std::vector<std::optional<MeasuredHistory>> out(set.size());
  for (std::size_t i = 0; i < set.size(); ++i) {
    const std::string& id = set.impacts[i].id;
    if (have.count(id)) out[i] = measured_history(read_block_track(data, id), id, shape, data);
  }
  return out;
}

std::size_t history_count(const std::vector<std::optional<MeasuredHistory>>& histories) {
  return static_cast<std::size_t>(std::count_if(histories.begin(), histories.end(),
                                                [](const auto& h) { return h.has_value(); }));
}

void ResidualSquares::add(const ReleaseResidual& r) {
  for (const auto& row : r.residual)
    for (std::size_t c = 0; c < kForceComponents; ++c)
      if (std::isfinite(row[c])) {
        sum[c] += row[c] * row[c];
        ++n[c];
      }
}

void ResidualSquares::add(const ResidualSquares& other) {
  for (std::size_t c = 0; c < kForceComponents; ++c) {
    sum[c] += other.sum[c];
    n[c] += other.n[c];
  }
}

std::array<double, kForceComponents> ResidualSquares::rms() const {
  std::array<double, kForceComponents> out;
  for (std::size_t c = 0; c < kForceComponents; ++c)
    out[c] = n[c] > 0 ? std::sqrt(sum[c] / static_cast<double>(n[c])) : kNaN;
  return out;
}

std::optional<ForceLawReport> force_law_from_tracks(
    const std::string& data, const ImpactSet& set, const Shape& shape, const Model& model,
    std::span<const double> params, const EngineOptions& engine,
    const stats::SparseOptions& options, const std::vector<std::vector<double>>& release_params) {
  const auto t0 = std::chrono::steady_clock::now();
  // measured_histories is aligned with the set: force_law_from_histories checks release_params.
  auto report = force_law_from_histories(measured_histories(data, set, shape), shape, model, params,
                                         engine, options, release_params);
  if (report) report->seconds = seconds_since(t0);
  return report;
}

std::optional<ForceLawReport> force_law_from_histories(
    const std::vector<std::optional<MeasuredHistory>>& histories, const Shape& shape,
    const Model& model, std::span<const double> params, const EngineOptions& engine,
    const stats::SparseOptions& options, const std::vector<std::vector<double>>& release_params,
    std::span<const ForceTerm* const> named) {
  if (!release_params.empty() && release_params.size() != histories.size())
    throw std::invalid_argument(
        "force_law_from_histories: release_params is not aligned with the histories");
  const auto t0 = std::chrono::steady_clock::now();
  ForceLawReport report;
  report.force_scale_min = std::numeric_limits<double>::infinity();
  report.force_scale_max = -std::numeric_limits<double>::infinity();
  std::vector<ReleaseResidual> residuals;
  report.base = release_params.empty() ? "population fit" : "per-release fits";
  for (std::size_t i = 0; i < histories.size(); ++i) {
    const auto& h = histories[i];
    if (!h) continue;
    const bool own = !release_params.empty() && !release_params[i].empty();
    ReleaseResidual r = force_residual(
        *h, model, shape, own ? std::span<const double>(release_params[i]) : params, engine);
    if (r.samples.empty()) continue;
    report.ids.push_back(h->id);
    report.samples += r.samples.size();
    report.force_scale_min = std::min(report.force_scale_min, h->force_scale);
    report.force_scale_max = std::max(report.force_scale_max, h->force_scale);
    report.geometry_mismatch_m = std::max(report.geometry_mismatch_m, h->geometry_mismatch_m);
    residuals.push_back(std::move(r));
  }
  if (residuals.size() < 2) return std::nullopt;
  report.laws = discover_force_law(residuals, options, named);
  report.map = residual_map(residuals);
  for (const ForceTerm* t : named) report.named.emplace_back(t->name);
  report.seconds = seconds_since(t0);
  return report;
}

nlohmann::json to_json(const ForceLawReport& report) {
  nlohmann::json laws = nlohmann::json::array();
  for (const ComponentLaw& law : report.laws) {
    nlohmann::json terms = nlohmann::json::array();
    for (const DiscoveredTerm& t : law.terms)
      if (t.selected)
        terms.push_back({{"name", t.term->name},
                         {"expression", t.term->expression},
                         {"unit", t.term->unit},
                         {"literature", t.term->literature},
                         {"coefficient", t.coefficient},
                         {"lo", t.lo},
                         {"hi", t.hi},
                         {"inclusion", t.inclusion}});
    laws.push_back({{"component", component_name(law.component)},
                    {"text", law.text},
                    {"releases", law.releases},
                    {"samples", law.samples},
                    {"rms_residual", law.rms_residual},
                    {"heldout_rms", law.heldout_rms},
                    {"terms", terms}});
  }
  return {{"ids", report.ids},
          {"samples", report.samples},
          {"force_scale", {report.force_scale_min, report.force_scale_max}},
          {"geometry_mismatch_m", report.geometry_mismatch_m},
          {"base", report.base},
          {"named", report.named},
          {"seconds", report.seconds},
          {"laws", laws},
          {"residual_map", to_json(report.map)}};
}

std::string found_law_text(const ForceLawReport& report) {
  std::string out;
  for (const ComponentLaw& law : report.laws)
    if (std::any_of(law.terms.begin(), law.terms.end(),
                    [](const DiscoveredTerm& t) { return t.selected; }))
      out += (out.empty() ? "" : "; ") + law.text;
  return out;
}

std::string format_text(const ForceLawReport& report) {
  std::string named;
  for (const std::string& n : report.named) named += (named.empty() ? "" : ", ") + n;
  std::string out = fmt::format(
      "force law {} ({}), from the contact histories of {} releases ({} "
      "contact samples; forces scaled x{:.4g}-{:.4g} to the lab block; largest geometry mismatch "
      "{:.2g} mm):\n",
      named.empty() ? "missing from the model" : "of the named terms " + named + ", fitted",
      report.base, report.ids.size(), report.samples, report.force_scale_min,
      report.force_scale_max, 1e3 * report.geometry_mismatch_m);
  for (const ComponentLaw& law : report.laws)
    out += fmt::format("  {:<10} {} (residual rms {:.4g}, held out after the law {:.4g})\n",
                       component_name(law.component), law.text, law.rms_residual, law.heldout_rms);
  return out + format_text(report.map);
}

}  // namespace ricochet::diagnosis
