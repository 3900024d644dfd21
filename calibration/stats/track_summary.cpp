#include "stats/track_summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "common/nan.hpp"

namespace ricochet::stats {
namespace {

// A contact force below this fraction of the track's largest is rounding, not a touch.
constexpr double kForceRoundoff = 1e-9;
// The contact criterion of the impact deck (liggghts-inputs/impact/setup.in: f_contact_frac, in
// contact while the contact force exceeds 0.2 of the block's weight) and its gravity (g_mps2).
constexpr double kContactWeightFraction = 0.2;
constexpr double kGravity_mps2 = 9.81;
// The averaging window of the bed's press after the peak (above_two_weights_after_peak_s) [s]:
// ten records of the campaigns' 0.2 ms tracks, a few of the grains' force chatter, short beside
// the 20 ms that the floor check reads.
constexpr double kPressWindow_s = 2e-3;

// Largest finite value of f(i) over the records, NaN when there is none.
template <class F>
double finite_max(std::size_t n, F f) {
  double m = kNaN;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = f(i);
    if (std::isfinite(v) && !(v <= m)) m = v;
  }
  return m;
}

std::string cell(double v, double scale) {
  return std::isfinite(v) ? fmt::format("{:>11.4g}", v * scale) : fmt::format("{:>11}", "-");
}

}  // namespace

double free_flight_mass_kg(const BlockTrack& tr) {
  // Free flight: the records before the first touch. Between two of them the kinetic energy
  // changes only by the work of gravity, on the translation (no torque, so the spin and the
  // rotational energy stay), hence Delta KE = m/2 Delta(vx^2 + vy^2).
  const std::size_t n = tr.size();
  const double peak =
      finite_max(n, [&](std::size_t i) { return std::hypot(tr.fcx[i], tr.fcy[i]); });
  std::size_t flying = 0;
  while (flying < n && !(std::hypot(tr.fcx[flying], tr.fcy[flying]) > kForceRoundoff * peak))
    ++flying;
  if (flying < 2) return kNaN;
  const std::size_t a = 0, b = flying - 1;
  const double dv2 =
      tr.vx[b] * tr.vx[b] + tr.vy[b] * tr.vy[b] - tr.vx[a] * tr.vx[a] - tr.vy[a] * tr.vy[a];
  const double m = 2 * (tr.ke_block[b] - tr.ke_block[a]) / dv2;
  return std::isfinite(m) && m > 0 ? m : kNaN;
}

std::optional<ContactWindow> contact_window(std::span<const double> fx, std::span<const double> fy,
                                            double mass_kg, std::span<const double> sigma_fx,
                                            std::span<const double> sigma_fy) {
  const std::size_t n = std::min(fx.size(), fy.size());
  auto force = [&](std::size_t i) { return std::hypot(fx[i], fy[i]); };
  const double peak_force = finite_max(n, force);
  // After the rebound, grains carried up with the block keep touching it with tens of newtons
  // while it flies centimetres above the surface (lab-triangles-blind.h5, T01: 10-45 N from 1
  // to 3 cm up, over 30 ms), which the first and last records above the criterion would count
  // as contact: hence the run around the peak.
  const double threshold = std::isfinite(mass_kg) ? kContactWeightFraction * mass_kg * kGravity_mps2
                                                  : kForceRoundoff * peak_force;
  // A force estimated from tracked accelerations (sigma_fcx, sigma_fcy given) bears only where it
  // is also clear of its noise: above 2 x hypot(s.e.), which noise alone exceeds in exp(-4) =
  // 1.8 % of free-flight records (a Rayleigh tail).
  auto noise = [&](std::size_t i) {
    if (i >= sigma_fx.size() || i >= sigma_fy.size()) return 0.0;
    const double e = std::hypot(sigma_fx[i], sigma_fy[i]);
    return std::isfinite(e) ? 2 * e : 0.0;
  };
  auto bearing = [&](std::size_t i) {
    return std::isfinite(force(i)) && force(i) > std::max(threshold, noise(i));
  };
  std::size_t peak = n;
  for (std::size_t i = 0; i < n; ++i)
    if (bearing(i) && (peak == n || force(i) > force(peak))) peak = i;
  if (peak == n) return std::nullopt;
  ContactWindow w{peak, peak, peak};
  while (w.first > 0 && bearing(w.first - 1)) --w.first;
  while (w.last + 1 < n && bearing(w.last + 1)) ++w.last;
  return w;
}

TrackSummary summarize_track(const BlockTrack& tr, const std::string& id) {
  TrackSummary s;
  s.id = id;
  s.records = tr.size();
  const std::size_t n = tr.size();
  if (n == 0) return s;
  s.block_mass_kg = tr.block_mass_kg;
  s.block_mass_source = "file";
  if (!std::isfinite(s.block_mass_kg)) {
    s.block_mass_kg = free_flight_mass_kg(tr);
    s.block_mass_source = std::isfinite(s.block_mass_kg) ? "free flight" : "unknown";
  }
  s.max_interval_s = finite_max(n - 1, [&](std::size_t i) { return tr.t[i + 1] - tr.t[i]; });
  // A touch: a contact force above kForceRoundoff of the track's largest. The deck records the
  // force as the body's total force plus its weight (impact/setup.in), which leaves a rounding
  // residue in free flight (3.6e-15 N in lab-cylinders.h5).
  auto force = [&](std::size_t i) { return std::hypot(tr.fcx[i], tr.fcy[i]); };
  const double peak_force = finite_max(n, force);
  for (std::size_t i = 0; i < n; ++i)
    if (std::isfinite(force(i)) && force(i) > kForceRoundoff * peak_force) {
      if (std::isnan(s.first_touch_s)) s.first_touch_s = tr.t[i];
      s.last_touch_s = tr.t[i];
    }
  // The contact window (contact_window): the run of records around the largest force in which
  // the force bears more than kContactWeightFraction of the block's weight.
  const auto window = contact_window(tr.fcx, tr.fcy, s.block_mass_kg, tr.sigma_fcx, tr.sigma_fcy);
  std::size_t last = n;
  if (window) {
    const std::size_t first = window->first, peak = window->peak;
    last = window->last;
    s.contact_start_s = tr.t[first];
    s.contact_end_s = tr.t[last];
    s.contact_duration_s = s.contact_end_s - s.contact_start_s;
    double lift = 0, above = 0;
    bool depth_known = true;
    for (std::size_t i = first; i <= last; ++i) {
      const double dt = i + 1 < n ? tr.t[i + 1] - tr.t[i] : (i > 0 ? tr.t[i] - tr.t[i - 1] : 0.0);
      const double up = std::isfinite(tr.fcy[i]) && tr.fcy[i] > 0 ? tr.fcy[i] * dt : 0.0;
      depth_known = depth_known && std::isfinite(tr.penetration[i]);
      lift += up;
      if (tr.penetration[i] < 0) above += up;
    }
    if (depth_known && lift > 0) s.lift_above_surface = above / lift;
    // The impact proper ends where the force no longer exceeds the weight: from there on the bed
    // carries the block rather than stopping it.
    if (const double weight = s.block_mass_kg * kGravity_mps2; std::isfinite(weight)) {
      std::size_t end = peak + 1;
      while (end < n && !(force(end) <= weight)) ++end;
      if (end < n) {
        s.impact_duration_s = tr.t[end] - s.contact_start_s;
        s.vy_impact_end_mps = tr.vy[end];
        if (tr.vy[first] < 0) s.impact_restitution = tr.vy[end] / -tr.vy[first];
      }
      // The force averaged over kPressWindow_s, so that the grains' chatter (single records of
      // a 300 N phase dip below 2 m g) does not end the phase; unbroken, so that a later rise
      // (the block climbing its crater's rim) is another phase, not the bed still pressing.
      const auto smoothed = [&](std::size_t i) {
        double sum = 0;
        std::size_t count = 0;
        for (std::size_t j = i; j-- > 0 && tr.t[i] - tr.t[j] <= kPressWindow_s / 2 + 1e-12;)
          sum += force(j), ++count;
        for (std::size_t j = i; j < n && tr.t[j] - tr.t[i] <= kPressWindow_s / 2 + 1e-12; ++j)
          sum += force(j), ++count;
        return sum / static_cast<double>(count);
      };
      std::size_t pressed = peak;
      while (pressed < last && smoothed(pressed + 1) > 2 * weight) ++pressed;
      s.above_two_weights_after_peak_s = tr.t[pressed] - tr.t[peak];
    }
  }
  s.peak_normal_force_N = finite_max(n, [&](std::size_t i) { return tr.fcy[i]; });
  s.peak_tangential_force_N = finite_max(n, [&](std::size_t i) { return std::abs(tr.fcx[i]); });
  s.peak_torque_Nm = finite_max(n, [&](std::size_t i) { return std::abs(tr.torque[i]); });
  s.max_penetration_m = finite_max(n, [&](std::size_t i) { return tr.penetration[i]; });
  if (last < n && std::isfinite(tr.penetration[last])) {
    s.final_penetration_m = tr.penetration[last];
    s.elastic_recovery_m = s.max_penetration_m - s.final_penetration_m;
  }
  s.max_overlap_d = finite_max(n, [&](std::size_t i) { return tr.overlap_d_max[i]; });
  return s;
}

const std::vector<TrackQuantity>& track_quantities() {
  static const std::vector<TrackQuantity> q = {
      {"max_interval", "s", "largest record interval [ms]", 1e3, &TrackSummary::max_interval_s},
      {"contact_duration", "s", "contact duration [ms]", 1e3, &TrackSummary::contact_duration_s},
      {"peak_normal_force", "N", "peak normal force fcy [N]", 1,
       &TrackSummary::peak_normal_force_N},
      {"peak_tangential_force", "N", "peak |fcx| [N]", 1, &TrackSummary::peak_tangential_force_N},
      {"peak_torque", "N*m", "peak |torque| [N*m]", 1, &TrackSummary::peak_torque_Nm},
      {"max_penetration", "m", "max penetration [mm]", 1e3, &TrackSummary::max_penetration_m},
      {"final_penetration", "m", "penetration at contact end [mm]", 1e3,
       &TrackSummary::final_penetration_m},
      {"elastic_recovery", "m", "elastic recovery [mm]", 1e3, &TrackSummary::elastic_recovery_m},
      {"max_overlap_d", "-", "max grain overlap / d [-]", 1, &TrackSummary::max_overlap_d},
      {"lift_above_surface", "-", "lift share above the surface [-]", 1,
       &TrackSummary::lift_above_surface},
      {"impact_duration", "s", "impact, to force < m g [ms]", 1e3,
       &TrackSummary::impact_duration_s},
      {"vy_impact_end", "m/s", "vy at the impact's end [m/s]", 1, &TrackSummary::vy_impact_end_mps},
      {"impact_restitution", "-", "impact's own vy restitution [-]", 1,
       &TrackSummary::impact_restitution},
      {"above_two_weights_after_peak", "s", "after the peak, force > 2 m g [ms]", 1e3,
       &TrackSummary::above_two_weights_after_peak_s},
      {"block_mass", "kg", "simulated block mass [kg]", 1, &TrackSummary::block_mass_kg},
  };
  return q;
}

TrackTable track_table(const std::string& path, const ImpactSet& set) {
  TrackTable t;
  t.source = path;
  t.releases = set.size();
  const auto ids = block_track_ids(path);
  if (ids.empty()) return t;
  const std::set<std::string> kept(ids.begin(), ids.end());
  std::set<std::string> used;
  for (const auto& im : set.impacts)
    if (kept.count(im.id)) {
      t.impacts.push_back(summarize_track(read_block_track(path, im.id), im.id));
      used.insert(im.id);
    }
  t.other_tracks = ids.size() - used.size();
  for (const auto& q : track_quantities()) {
    std::vector<double> v;
    for (const auto& s : t.impacts) v.push_back(s.*(q.member));
    t.over_impacts.push_back(summarize(v));
  }
  return t;
}

nlohmann::json to_json(const TrackTable& t) {
  nlohmann::json summary = nlohmann::json::object();
  const auto& qs = track_quantities();
  for (std::size_t k = 0; k < qs.size(); ++k) {
    const Summary& s = t.over_impacts[k];
    summary[qs[k].key] = {{"n", s.n},     {"mean", s.mean}, {"std", s.std},
                          {"min", s.min}, {"max", s.max},   {"unit", qs[k].unit}};
  }
  nlohmann::json impacts = nlohmann::json::array();
  for (const auto& s : t.impacts) {
    nlohmann::json j = {{"id", s.id},
                        {"records", s.records},
                        {"contact_start", s.contact_start_s},
                        {"contact_end", s.contact_end_s},
                        {"first_touch", s.first_touch_s},
                        {"last_touch", s.last_touch_s},
                        {"block_mass_source", s.block_mass_source}};
    for (const auto& q : qs) j[q.key] = s.*(q.member);
    impacts.push_back(j);
  }
  return {
      {"group", kTracksGroup},          {"releases", t.releases}, {"with_track", t.impacts.size()},
      {"other_tracks", t.other_tracks}, {"summary", summary},     {"impacts", impacts}};
}

std::string format_text(const TrackTable& t) {
  std::string out =
      fmt::format("Tracks ({}): {} of {} releases", kTracksGroup, t.impacts.size(), t.releases);
  if (t.other_tracks > 0)
    out += fmt::format("; {} more of impacts not in this set (no rebound, or filtered out)",
                       t.other_tracks);
  out += "\n";
  if (t.impacts.empty()) return out;
  std::size_t rmin = t.impacts.front().records, rmax = rmin;
  for (const auto& s : t.impacts) {
    rmin = std::min(rmin, s.records);
    rmax = std::max(rmax, s.records);
  }
  out += fmt::format("{:<34}{:>5}{:>11}{:>11}{:>11}{:>11}\n", "per impact", "n", "mean", "std",
                     "min", "max");
  out += fmt::format("{:<34}{:>5}{:>11}{:>11}{:>11}{:>11}\n", "records", t.impacts.size(), "", "",
                     rmin, rmax);
  const auto& qs = track_quantities();
  for (std::size_t k = 0; k < qs.size(); ++k) {
    const Summary& s = t.over_impacts[k];
    out += fmt::format("{:<34}{:>5}", qs[k].label, s.n) + cell(s.mean, qs[k].print_scale) +
           cell(s.std, qs[k].print_scale) + cell(s.min, qs[k].print_scale) +
           cell(s.max, qs[k].print_scale) + "\n";
  }
  out +=
      "Contact: the run of records around the peak force above 0.2 x the block's weight (and "
      "above 2 s.e. where the force is estimated from tracked accelerations). Forces "
      "and torque are the simulated block's (a slab carries a fraction of the lab block). n: "
      "tracks with that column (older tracks have no torque or overlap). Impact: from the "
      "contact's start to the first record after the peak whose force is at most the block's "
      "weight; its restitution is vy there over -vy at the contact's start. Per impact: --json.\n";
  return out;
}

}  // namespace ricochet::stats
