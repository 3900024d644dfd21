#include "diagnosis/track_figure.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "impact/block_track.hpp"
#include "stats/track_summary.hpp"

namespace ricochet::diagnosis {
namespace {

using report::Panel;
using report::Series;

// LIGGGHTS records shown around the contact window [s]: the approach and the departure.
constexpr double kMargin_s = 5e-3;
// Engine steps (1e-5 s) drawn at most per curve: a 20 ms contact is 2,000 steps, more than a
// page needs and more than the report keeps as vector graphics.
constexpr std::size_t kMaxEnginePoints = 400;

struct Curves {
  std::vector<double> t_ms, normal_N, tangential_N, penetration_mm;
};

// The release whose track the figure shows (nullptr when none has one).
const Impact* chosen_release(const ImpactSet& set, const std::vector<std::string>& ids,
                             const std::string& preferred_id) {
  const std::set<std::string> kept(ids.begin(), ids.end());
  for (const auto& im : set.impacts)
    if (im.id == preferred_id && kept.count(im.id)) return &im;
  for (const auto& im : set.impacts)
    if (kept.count(im.id)) return &im;
  return nullptr;
}

Panel panel(const char* title, const char* ylabel, const Curves& dem, const Curves& law,
            std::vector<double> Curves::*member) {
  Panel p;
  p.title = title;
  p.xlabel = "time since the contact starts [ms]";
  p.ylabel = ylabel;
  p.series.push_back(Series{.title = "LIGGGHTS track",
                            .x = dem.t_ms,
                            .y = dem.*member,
                            .style = "lines",
                            .color = report::colour::kBlue});
  p.series.push_back(Series{.title = "reduced law, same V_in",
                            .x = law.t_ms,
                            .y = law.*member,
                            .style = "lines",
                            .color = report::colour::kVermillion});
  return p;
}

}  // namespace

std::optional<NamedFigure> contact_track_figure(const std::string& data, const ImpactSet& set,
                                                const Shape& shape, const Model& model,
                                                std::span<const double> params,
                                                const EngineOptions& engine,
                                                const std::string& preferred_id,
                                                const std::string& title) {
  const Impact* im = chosen_release(set, block_track_ids(data), preferred_id);
  if (!im) return std::nullopt;
  const BlockTrack track = read_block_track(data, im->id);
  const stats::TrackSummary dem = stats::summarize_track(track, im->id);

  // The slab's forces per unit length are the lab block's (same section, same speeds): scale
  // them by the ratio of the masses, which is the ratio of the lengths.
  double scale = 1;
  std::string scaling;
  if (std::isfinite(dem.block_mass_kg)) {
    scale = shape.mass_kg / dem.block_mass_kg;
    scaling = fmt::format(
        "LIGGGHTS forces are scaled to the lab block, x {:.3g} = m_lab / m_slab = {:.4g} kg / "
        "{:.4g} kg (the slab carries the fraction slab width / block length of the block; its "
        "mass {})",
        scale, shape.mass_kg, dem.block_mass_kg,
        dem.block_mass_source == "file" ? "as the file records it"
                                        : "from the track's free flight before the contact");
  } else {
    scaling =
        "LIGGGHTS forces are the simulated block's, unscaled: the file gives no block mass and "
        "the track no free flight to infer it from";
  }
  const double t0 = std::isfinite(dem.contact_start_s) ? dem.contact_start_s : track.t.front();
  const double t1 = std::isfinite(dem.contact_end_s) ? dem.contact_end_s : track.t.back();
  Curves liggghts;
  for (std::size_t i = 0; i < track.size(); ++i) {
    if (track.t[i] < t0 - kMargin_s || track.t[i] > t1 + kMargin_s) continue;
    liggghts.t_ms.push_back(1e3 * (track.t[i] - t0));
    liggghts.normal_N.push_back(scale * track.fcy[i]);
    liggghts.tangential_N.push_back(scale * track.fcx[i]);
    liggghts.penetration_mm.push_back(1e3 * track.penetration[i]);
  }

  double liggghts_touch_mm = NAN;
  for (std::size_t i = 0; i < liggghts.t_ms.size(); ++i)
    if (liggghts.t_ms[i] == 0.0) liggghts_touch_mm = liggghts.penetration_mm[i];

  Trace trace;
  const CollisionCase collision{im->vin, im->alpha_in.value_or(0.0)};
  const CollisionResult result = simulate(model, shape, collision, params, engine, &trace);
  std::size_t first = 0;
  while (first < trace.t.size() && trace.fn[first] == 0 && trace.ft[first] == 0) ++first;
  const double te0 = first < trace.t.size() ? trace.t[first] : 0.0;
  const std::size_t stride =
      std::max<std::size_t>(1, (trace.t.size() + kMaxEnginePoints - 1) / kMaxEnginePoints);
  Curves law;
  double law_peak = 0;
  for (std::size_t k = 0; k < trace.t.size(); ++k) {
    law_peak = std::max(law_peak, trace.fn[k]);
    if (k % stride != 0 && k + 1 != trace.t.size()) continue;
    law.t_ms.push_back(1e3 * (trace.t[k] - te0));
    law.normal_N.push_back(trace.fn[k]);
    law.tangential_N.push_back(trace.ft[k]);
    law.penetration_mm.push_back(1e3 * trace.h[k]);
  }

  NamedFigure f;
  f.stem = "contact-track-" + im->id;
  f.figure.title = fmt::format("{}: impact {}, LIGGGHTS against the reduced law", title, im->id);
  f.figure.columns = 3;
  f.figure.panels = {
      panel("normal contact force", "force [N]", liggghts, law, &Curves::normal_N),
      panel("tangential contact force", "force [N]", liggghts, law, &Curves::tangential_N),
      panel("penetration", "depth below the surface [mm]", liggghts, law, &Curves::penetration_mm)};
  // Where the impact proper ends (the force falls to the block's weight, stats/track_summary.hpp):
  // after it a long contact is a block carried out of its crater, not an impact.
  std::string impact_end;
  if (std::isfinite(dem.impact_duration_s)) {
    // A finite impact duration implies a contact window, whose start is t0.
    const double t_ms = 1e3 * dem.impact_duration_s;
    f.figure.panels[0].series.push_back(Series{.title = "impact's end (force = weight)",
                                               .x = {t_ms, t_ms},
                                               .y = {0.0, scale * dem.peak_normal_force_N},
                                               .style = "lines",
                                               .color = report::colour::kGrey});
    impact_end = fmt::format(
        " The impact proper (LIGGGHTS, grey line: until the force first falls to the block's "
        "weight) lasts {:.1f} ms and gives back vy = {:.3g} m/s, {:.2f} of the landing vy; "
        "the rest of the contact is the block carried by a force of about its weight.",
        1e3 * dem.impact_duration_s, dem.vy_impact_end_mps, dem.impact_restitution);
  }
  f.caption = fmt::format(
      "One impact of this campaign in time: the contact force and the penetration of release {} "
      "(V_in = ({:.3g} m/s, {:.3g} m/s, {:.3g} rad/s)) from its LIGGGHTS track, beside the "
      "reduced law ({}) simulated from the same incident state. Normal = the vertical force fcy "
      "(LIGGGHTS) or fn (reduced law), tangential = the horizontal fcx or ft, paper frame (x in "
      "the flight direction, y up) on a horizontal bed; time from the start of each contact "
      "(LIGGGHTS: the run of records around the peak above 0.2 of the block's weight). {}. "
      "Penetration: the block's lowest point below the levelled surface (LIGGGHTS; negative "
      "above it, and the grains standing above the levelled surface are touched before it is "
      "reached, at {:.1f} mm here) and the deepest vertex overlap with the ground line (reduced "
      "law). Contact "
      "{:.1f} ms and peak normal force {:.4g} N (LIGGGHTS, scaled), against {:.1f} ms and {:.4g} "
      "N (reduced law, status {}).{}",
      im->id, im->vin[kVx], im->vin[kVy], im->vin[kW], fmt::join(model.effect_names(), " + "),
      scaling, liggghts_touch_mm, 1e3 * dem.contact_duration_s, scale * dem.peak_normal_force_N,
      1e3 * result.contact_duration_s, law_peak, status_name(result.status), impact_end);
  return f;
}

}  // namespace ricochet::diagnosis
