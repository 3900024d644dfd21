#include "impact_extract.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "common/nan.hpp"
#include "frames.hpp"

namespace ricochet::dem {

namespace {

// A column name without its unit: "torque[N*m]" -> "torque".
std::string bare_name(const std::string& name) {
  const auto b = name.find('[');
  std::string s = b == std::string::npos ? name : name.substr(0, b);
  while (!s.empty() && s.back() == ' ') s.pop_back();
  while (!s.empty() && s.front() == ' ') s.erase(0, 1);
  return s;
}

// The deck writes theta in (-2 pi, 2 pi]: unwrap to a continuous angle.
void unwrap_theta(std::vector<double>& theta) {
  for (std::size_t i = 1; i < theta.size(); ++i) {
    const double d = theta[i] - theta[i - 1];
    const double turn = 2 * std::numbers::pi;
    theta[i] -= turn * std::round(d / turn);
  }
}

// Nearest record to each frame time t0 + k / fps (the camera samples the motion; it does not
// average it).
kinematics::Track frames(const BlockTrack& tr, double fps) {
  kinematics::Track out;
  out.source = "LIGGGHTS block track";
  if (tr.size() == 0) return out;
  std::size_t j = 0;
  for (std::size_t k = 0;; ++k) {
    const double tk = fps > 0 ? tr.t.front() + static_cast<double>(k) / fps : kNaN;
    if (fps > 0 && tk > tr.t.back()) break;
    if (fps <= 0) {
      if (k >= tr.size()) break;
      j = k;
    } else {
      while (j + 1 < tr.size() && std::abs(tr.t[j + 1] - tk) <= std::abs(tr.t[j] - tk)) ++j;
      if (!out.t.empty() && tr.t[j] <= out.t.back()) continue;
    }
    out.t.push_back(tr.t[j]);
    out.x.push_back(tr.x[j]);
    out.y.push_back(tr.y[j]);
    out.theta.push_back(tr.theta[j]);
  }
  return out;
}

}  // namespace

BlockTrack read_deck_track(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read the block track " + path);
  BlockTrack tr;
  // Columns of the file: from its title line, else the layout before the title named them
  // (twelve columns; a thirteenth is the torque).
  const auto& all = BlockTrack::column_names();
  std::vector<std::string> names(all.begin(), all.begin() + 13);
  std::string line;
  bool titled = false;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      if (titled) continue;
      std::istringstream ls(line.substr(1));
      std::vector<std::string> title;
      for (std::string w; ls >> w;) title.push_back(w);
      if (!title.empty() && bare_name(title[0]) == "t") {
        names = title;
        titled = true;
      }
      continue;
    }
    std::istringstream ls(line);
    std::vector<double> v;
    for (std::string cell; ls >> cell;)
      v.push_back(std::strtod(cell.c_str(), nullptr));  // "nan" reads as NaN
    // A line cut by a crash has fewer cells; a title-less legacy file has 12.
    const std::size_t need = titled ? names.size() : 12;
    if (v.size() < need) continue;
    std::size_t it = 0;
    while (it < names.size() && bare_name(names[it]) != "t") ++it;
    if (it >= v.size()) continue;
    if (!tr.t.empty() && v[it] <= tr.t.back()) continue;
    const std::size_t row = tr.t.size();
    for (std::size_t c = 0; c < std::min(v.size(), names.size()); ++c)
      if (auto* col = tr.column(names[c])) {
        col->resize(row, kNaN);
        col->push_back(v[c]);
      }
    tr.pad();
  }
  tr.pad();
  unwrap_theta(tr.theta);
  return tr;
}

bool read_track(ImpactResult& r, const std::string& out,
                const std::vector<std::pair<double, double>>& overlaps) {
  try {
    r.track = read_deck_track(out + ".track.txt");
    r.track.block_mass_kg = r.block_mass_kg;
  } catch (const std::exception& e) {
    if (r.ok()) {
      r.status = "extraction_failed";
      r.message = e.what();
    }
    return false;
  }
  if (!overlaps.empty()) {
    std::size_t k = 0;
    for (std::size_t i = 0; i < r.track.size(); ++i) {
      const double t = r.track.t[i];
      while (k + 1 < overlaps.size() && overlaps[k + 1].first <= t + 0.25 * r.dt_s) ++k;
      if (std::abs(overlaps[k].first - t) <= 0.25 * r.dt_s)
        r.track.overlap_d_max[i] = overlaps[k].second;
    }
  }
  for (double p : r.track.penetration) r.penetration_max_m = std::max(r.penetration_max_m, p);
  return true;
}

void explain_status(ImpactResult& r, double t_max) {
  if (r.status == "no_rebound")
    r.message = fmt::format(
        "the block stayed in the bed (slower than v_rest_mps while in contact), "
        "maximum penetration {:.4f} m",
        r.penetration_max_m);
  if (r.status == "timeout")
    r.message = fmt::format("no end of the rebound within t_max_s = {} s", t_max);
  if (r.status == "end_wall")
    r.message =
        "the block came too close to an end wall (setup.in: x_wall_front, x_wall_back): "
        "use a longer bed";
}

std::optional<std::pair<std::size_t, std::size_t>> force_window(ImpactResult& r,
                                                                const ImpactSpec& spec,
                                                                const ImpactContext& ctx,
                                                                const Shape& shape,
                                                                const Simulated& sim) {
  const BlockTrack& tr = r.track;
  const double threshold =
      run_param(spec, *ctx.decks, "f_contact_frac") * sim.block_mass * kDeckGravity_mps2;
  std::size_t i0 = tr.size(), i1 = tr.size();
  for (std::size_t i = 0; i < tr.size(); ++i) {
    if (tr.t[i] > sim.deck_contact_end) break;
    if (std::hypot(tr.fcx[i], tr.fcy[i]) > threshold && tr.penetration[i] > -2 * ctx.bed.r_max_m) {
      if (i0 == tr.size()) i0 = i;
      i1 = i;
    }
  }
  if (i0 == tr.size()) {
    r.status = "extraction_failed";
    r.message = "no contact force in the recorded track";
    return std::nullopt;
  }
  i1 = std::min(i1 + 1, tr.size() - 1);  // first record after the last contact
  r.force_contact_start_s = tr.t[i0];
  r.force_contact_end_s = tr.t[i1];
  r.v_start_direct = {tr.vx[i0], tr.vy[i0], tr.w[i0]};
  r.v_end_direct = {tr.vx[i1], tr.vy[i1], tr.w[i1]};
  // Energy lost over the contact, kinetic plus potential, for the lab-length block (the slab
  // carries block_mass / shape.mass_kg of it).
  const double scale = shape.mass_kg / sim.block_mass;
  const double e0 = tr.ke_block[i0] + sim.block_mass * kDeckGravity_mps2 * tr.y[i0];
  const double e1 = tr.ke_block[i1] + sim.block_mass * kDeckGravity_mps2 * tr.y[i1];
  r.energy_dissipated_J = (e0 - e1) * scale;
  r.energy_dissipated_frac = (e0 - e1) / tr.ke_block[i0];
  return std::pair{i0, i1};
}

void measure_crater(ImpactResult& r, const Simulated& sim, const Shape& shape, double r_max_m,
                    double crater_bin, std::size_t i0, std::size_t i1) {
  const auto& before = sim.before;
  const auto& after = sim.after;
  if (before.empty() || before.size() != after.size()) return;
  const double reach = shape.bounding_radius();
  const auto n = before.size();
  std::size_t best = n;
  for (std::size_t b = 0; b < n; ++b) {
    const double xb = (static_cast<double>(b) + 0.5) * crater_bin;
    if (xb < r.track.x[i0] - reach || xb > r.track.x[i1] + reach) continue;
    const double drop = before[b] - after[b];
    if (std::isfinite(drop) && (best == n || drop > before[best] - after[best])) best = b;
  }
  if (best == n) return;
  r.crater_depth_m = std::max(0.0, before[best] - after[best]);
  std::size_t lo = best, hi = best;
  auto dropped = [&](std::size_t b) { return before[b] - after[b] > r_max_m; };
  if (!dropped(best)) return;
  while (lo > 0 && dropped(lo - 1)) --lo;
  while (hi + 1 < n && dropped(hi + 1)) ++hi;
  r.crater_width_m = static_cast<double>(hi - lo + 1) * crater_bin;
}

bool extract_release(ImpactResult& r, const ImpactSpec& spec, const ImpactContext& ctx,
                     const Shape& shape) {
  kinematics::ReconstructOptions ro;
  std::string window = ctx.extract.window;
  if (window.empty()) window = "force";
  if (window == "ground") {
    ro.ground_y_m = ctx.bed.z_surface_m;
    ro.contact_radius_m = shape.depth_below_centroid(spec.alpha_in_rad);
  } else if (window == "force") {
    ro.contact_start_s = r.force_contact_start_s;
    ro.contact_end_s = r.force_contact_end_s;
  }
  try {
    r.reconstruction = kinematics::reconstruct(frames(r.track, ctx.extract.fps), ro);
  } catch (const std::exception& e) {
    r.status = "extraction_failed";
    r.message = std::string("reconstruction: ") + e.what();
    return false;
  }
  const auto& rec = r.reconstruction;
  if (!(rec.vout[kVy] > 0) || !(rec.vin[kVy] < 0)) {
    r.status = "extraction_failed";
    r.message = fmt::format("reconstructed vin_y = {:.3f}, vout_y = {:.3f} m/s: not a rebound",
                            rec.vin[kVy], rec.vout[kVy]);
    return false;
  }
  r.impact = kinematics::to_impact(rec, spec.id, shape.name);
  Impact& im = r.impact;
  im.alpha_in = spec.alpha_in_rad;
  im.penetration = r.penetration_max_m;
  im.extra = {r.energy_dissipated_frac, r.crater_depth_m,
              r.crater_width_m,         r.v_start_direct[kVx],
              r.v_start_direct[kVy],    r.v_start_direct[kW],
              r.v_end_direct[kVx],      r.v_end_direct[kVy],
              r.v_end_direct[kW],       r.force_contact_end_s - r.force_contact_start_s};
  r.message = fmt::format("V_out = ({:.3f} m/s, {:.3f} m/s, {:.2f} rad/s)", rec.vout[kVx],
                          rec.vout[kVy], rec.vout[kW]);
  if (r.grains_lost > 0) r.message += fmt::format("; {} grain(s) left the box", r.grains_lost);
  return true;
}

}  // namespace ricochet::dem
