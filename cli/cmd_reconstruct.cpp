// `ricochet reconstruct TRACK.csv`: incident and reflected velocities of one release from its
// tracked points (paper section 2.3, Figs. 7-8). See docs/commands/reconstruct.md.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "impact/impact_set.hpp"
#include "kinematics/reconstruct.hpp"
#include "report/plot.hpp"
#include "shared_options.hpp"

namespace ricochet::cli {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

struct ReconstructCliOptions {
  std::string track, window, id, shape = "unknown", figures;
  std::optional<double> pixel_size, gravity, ground, radius, sigma_position;
  bool free_gravity = false, y_down = false;
  double k_sigma = kinematics::ReconstructOptions{}.detection_k_sigma;
  std::size_t guard = kinematics::ReconstructOptions{}.detection_guard_points;
  OutputOptions output;
};

json per_component(const Vel3& v) {
  return {{"vx", v[kVx]}, {"vy", v[kVy]}, {"w", v[kW]}};
}

std::pair<double, double> parse_window(const std::string& text) {
  const auto comma = text.find(',');
  auto number = [&](const std::string& cell) {
    try {
      std::size_t used = 0;
      const double v = std::stod(cell, &used);
      if (used != cell.size() || !std::isfinite(v)) throw std::invalid_argument("bad");
      return v;
    } catch (const std::exception&) {
      throw InputError("<command line>", 0, "--window",
                       "'" + cell + "' is not a time in s (expected T0,T1)");
    }
  };
  if (comma == std::string::npos)
    throw InputError("<command line>", 0, "--window", "expected T0,T1 in s, got '" + text + "'");
  const double t0 = number(text.substr(0, comma)), t1 = number(text.substr(comma + 1));
  if (!(t0 < t1)) throw InputError("<command line>", 0, "--window", "T0 must be smaller than T1");
  return {t0, t1};
}

/// Paper Fig. 8: x(t), y(t), theta(t) with the two free-flight fits and the contact window.
void draw(const kinematics::Track& tr, const kinematics::Reconstruction& r,
          const std::string& path) {
  report::Figure fig;
  fig.title = "Trajectory reconstruction of " + tr.source + " (paper Fig. 8)";
  fig.width_px = 1350;
  fig.height_px = 420;
  const char* names[3] = {"x", "y", "theta"};
  const char* units[3] = {"m", "m", "rad"};
  const std::vector<double>* data[3] = {&tr.x, &tr.y, &tr.theta};
  for (int c = 0; c < 3; ++c) {
    report::Panel p;
    p.title = std::string(names[c]) + "(t)";
    p.xlabel = "t [s]";
    p.ylabel = std::string(names[c]) + " [" + units[c] + "]";
    p.key = "";  // the default: under the plot, never over data
    report::Series pts;
    pts.title = "tracked";
    pts.style = "points";
    pts.point_type = 6;
    pts.x = tr.t;
    pts.y = *data[c];
    p.series.push_back(pts);
    auto curve = [&](const char* title, double t_from, double t_to, double te, double pos,
                     double vel, double g, const char* color) {
      report::Series s;
      s.title = title;
      s.color = color;
      for (int k = 0; k <= 50; ++k) {
        const double t = t_from + (t_to - t_from) * k / 50.0, d = t - te;
        s.x.push_back(t);
        s.y.push_back(pos + vel * d - (c == kVy ? 0.5 * g * d * d : 0.0));
      }
      p.series.push_back(s);
    };
    curve("incoming fit", tr.t.front(), r.contact_start_s, r.contact_start_s, r.position_in[c],
          r.vin[c], r.gravity_before_mps2, report::colour::kVermillion);
    curve("outgoing fit", r.contact_end_s, tr.t.back(), r.contact_end_s, r.position_out[c],
          r.vout[c], r.gravity_after_mps2, report::colour::kBlue);
    double lo = *std::min_element(data[c]->begin(), data[c]->end());
    double hi = *std::max_element(data[c]->begin(), data[c]->end());
    for (double t : {r.contact_start_s, r.contact_end_s}) {
      report::Series w;
      w.title = t == r.contact_start_s ? "contact window" : "";
      w.color = report::colour::kGrey;
      w.x = {t, t};
      w.y = {lo, hi};
      p.series.push_back(w);
    }
    fig.panels.push_back(p);
  }
  report::render(fig, path);
}

kinematics::ReconstructOptions reconstruct_options(const ReconstructCliOptions& o) {
  kinematics::ReconstructOptions opt;
  if (!o.window.empty()) {
    const auto [t0, t1] = parse_window(o.window);
    opt.contact_start_s = t0;
    opt.contact_end_s = t1;
  }
  if (o.free_gravity) opt.gravity_mps2.reset();
  if (o.gravity) {
    if (!(std::isfinite(*o.gravity) && *o.gravity > 0))
      throw InputError("<command line>", 0, "--gravity",
                       "must be a positive acceleration in m/s^2");
    opt.gravity_mps2 = *o.gravity;
  }
  if (o.ground.has_value() != o.radius.has_value())
    throw InputError("<command line>", 0, o.ground ? "--radius" : "--ground",
                     "the ground-level criterion needs both --ground Y and --radius R (m)");
  opt.ground_y_m = o.ground;
  opt.contact_radius_m = o.radius;
  if (!(o.k_sigma > 0)) throw InputError("<command line>", 0, "--k-sigma", "must be positive");
  opt.detection_k_sigma = o.k_sigma;
  opt.detection_guard_points = o.guard;
  return opt;
}

// One release in the impact-set schema, with the standard errors as sigma columns.
void write_release(const ReconstructCliOptions& o, const kinematics::Reconstruction& r) {
  ImpactSet set;
  set.source = o.track;
  set.comments.push_back("ricochet reconstruct " + o.track + " (window " + r.window_method + ")");
  set.impacts.push_back(
      kinematics::to_impact(r, o.id.empty() ? fs::path(o.track).stem().string() : o.id, o.shape));
  write_impact_set(set, o.output.out);
}

json result_json(const ReconstructCliOptions& o, const kinematics::Reconstruction& r,
                 const kinematics::ReconstructOptions& opt,
                 const std::vector<std::string>& figures) {
  json doc;
  doc["command"] = "reconstruct";
  doc["source"] = o.track;
  doc["units"] = {{"vx", "m/s"}, {"vy", "m/s"}, {"w", "rad/s"}};
  doc["vin"] = per_component(r.vin);
  doc["sigma_vin"] = per_component(r.sigma_vin);
  doc["vout"] = per_component(r.vout);
  doc["sigma_vout"] = per_component(r.sigma_vout);
  doc["window"] = {{"start_s", r.contact_start_s},
                   {"end_s", r.contact_end_s},
                   {"duration_s", r.contact_end_s - r.contact_start_s},
                   {"detected", r.window_detected},
                   {"method", r.window_method}};
  doc["points_before"] = r.points_before;
  doc["points_after"] = r.points_after;
  doc["flagged_points"] = r.flagged_points;
  doc["gravity"] = {{"imposed", opt.gravity_mps2.has_value()},
                    {"before_mps2", r.gravity_before_mps2},
                    {"after_mps2", r.gravity_after_mps2},
                    {"sigma_before_mps2", r.sigma_gravity_before_mps2},
                    {"sigma_after_mps2", r.sigma_gravity_after_mps2}};
  doc["noise"] = {{"sigma_position_m", r.sigma_position_m},
                  {"sigma_theta_rad", r.sigma_theta_rad},
                  {"source", r.sigma_source}};
  doc["rms_residual_m"] = {{"before", r.rms_residual_before_m}, {"after", r.rms_residual_after_m}};
  doc["figures"] = figures;
  doc["out"] = o.output.out.empty() ? json(nullptr) : json(o.output.out);
  return doc;
}

void print_text(const ReconstructCliOptions& o, const kinematics::Reconstruction& r,
                const kinematics::ReconstructOptions& opt,
                const std::vector<std::string>& figures) {
  std::cout << fmt::format(
      "{}: contact window [{:.5f}, {:.5f}] s ({}), {} points before, {} after\n", o.track,
      r.contact_start_s, r.contact_end_s, r.window_method, r.points_before, r.points_after);
  std::cout << fmt::format("  {:<8}{:>20}{:>20}\n", "", "V_in (+- s.e.)", "V_out (+- s.e.)");
  const char* labels[3] = {"V^x", "V^y", "omega"};
  const char* units[3] = {"m/s", "m/s", "rad/s"};
  for (int c = 0; c < 3; ++c)
    std::cout << fmt::format("  {:<8}{:>20}{:>20}  [{}]\n", labels[c],
                             fmt::format("{:.3f} +- {:.3f}", r.vin[c], r.sigma_vin[c]),
                             fmt::format("{:.3f} +- {:.3f}", r.vout[c], r.sigma_vout[c]), units[c]);
  std::cout << fmt::format("  noise: {:.3g} m, {:.3g} rad ({}); gravity {:.3f} / {:.3f} m/s^2{}\n",
                           r.sigma_position_m, r.sigma_theta_rad, r.sigma_source,
                           r.gravity_before_mps2, r.gravity_after_mps2,
                           opt.gravity_mps2 ? " (imposed)" : " (fitted)");
  if (r.flagged_points)
    std::cout << fmt::format("  {} tracked points beyond {:.1f} sigma kept in the fits\n",
                             r.flagged_points, o.k_sigma);
  for (const std::string& f : figures) std::cout << "wrote " << f << "\n";
  if (!o.output.out.empty()) std::cout << "wrote " << o.output.out << "\n";
}

void run(const ReconstructCliOptions& o) {
  require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
  kinematics::Track track = kinematics::read_track_csv(o.track, o.pixel_size, o.y_down);
  if (o.sigma_position) {
    if (!(*o.sigma_position > 0))
      throw InputError("<command line>", 0, "--sigma-position", "must be a positive length in m");
    track.sigma_position_m = *o.sigma_position;
  }
  const kinematics::ReconstructOptions opt = reconstruct_options(o);
  kinematics::Reconstruction r;
  try {
    r = kinematics::reconstruct(track, opt);
  } catch (const std::invalid_argument& e) {
    // Not enough free flight, no contact found...: the user's track or options are at fault.
    throw InputError(o.track, 0, "", e.what());
  }
  std::vector<std::string> figures;
  if (!o.figures.empty()) {
    const std::string path =
        (fs::path(o.figures) / ("reconstruct_" + fs::path(o.track).stem().string() + ".svg"))
            .string();
    draw(track, r, path);
    figures.push_back(path);
  }
  if (!o.output.out.empty()) write_release(o, r);
  if (o.output.json) {
    print_json(result_json(o, r, opt, figures));
    return;
  }
  print_text(o, r, opt, figures);
}

}  // namespace

void add_reconstruct_command(CLI::App& app) {
  auto o = std::make_shared<ReconstructCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "reconstruct",
      "Incident and reflected velocities of one release from its tracked points (paper section "
      "2.3): ballistic fits before and after the contact window, with standard errors");
  sub->add_option("TRACK", o->track, "Track CSV: t[s], x, y, mark_x, mark_y (px, mm or m)")
      ->required();
  sub->add_option("--pixel-size", o->pixel_size, "Pixel size [m/px] for px columns");
  sub->add_flag("--y-down", o->y_down, "Image coordinates: y grows downwards (negated on reading)");
  sub->add_option("--window", o->window, "Contact window T0,T1 [s] (default: detected)");
  auto* g = sub->add_option("--gravity", o->gravity,
                            fmt::format("Gravity imposed in y(t) [m/s^2] (default {:g})",
                                        kinematics::ReconstructOptions{}.gravity_mps2.value_or(0)));
  auto* fg =
      sub->add_flag("--free-gravity", o->free_gravity, "Fit the quadratic coefficient of y(t)");
  g->excludes(fg);
  sub->add_option(
      "--ground", o->ground,
      "Ground level [m]: with --radius, contact is y <= ground + radius (paper Fig. 8b)");
  sub->add_option("--radius", o->radius, "Contact radius of the block [m] (with --ground)");
  sub->add_option("--k-sigma", o->k_sigma, "Detection threshold in standard deviations")
      ->capture_default_str();
  sub->add_option("--guard", o->guard, "Points dropped next to a detected contact window")
      ->capture_default_str();
  sub->add_option("--sigma-position", o->sigma_position,
                  "Known pointing uncertainty of one tracked point [m] (default: from residuals)");
  sub->add_option("--id", o->id, "Release id written by --out (default: the track's file name)");
  sub->add_option("--shape", o->shape, "Block shape written by --out")->capture_default_str();
  add_figures_option(sub, o->figures, "an SVG of x(t), y(t), theta(t) and the fits");
  add_output_options(sub, o->output);
  check_range(sub, "--pixel-size", 1e-12, 1e3);
  check_range(sub, "--gravity", 0, 1e3);
  check_range(sub, "--radius", 1e-6, 1e3);
  check_range(sub, "--k-sigma", 1e-3, 1e3);
  check_range(sub, "--guard", 0, 1e6);
  check_range(sub, "--sigma-position", 1e-12, 1e3);
  sub->callback([o] { run(*o); });
}

}  // namespace ricochet::cli
