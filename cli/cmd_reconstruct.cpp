// `ricochet reconstruct TRACK.csv`: incident and reflected velocities of one release from its
// tracked points (paper section 2.3, Figs. 7-8). See docs/commands/reconstruct.md.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "engine/shape.hpp"
#include "impact/block_track.hpp"
#include "impact/impact_set.hpp"
#include "kinematics/reconstruct.hpp"
#include "kinematics/track_forces.hpp"
#include "report/plot.hpp"
#include "shared_options.hpp"
#include "stats/robust.hpp"

namespace ricochet::cli {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

struct ReconstructCliOptions {
  std::vector<std::string> tracks;
  std::string window, id, shape = "unknown", figures;
  std::optional<double> pixel_size, gravity, ground, radius, sigma_position, mass, inertia;
  bool free_gravity = false, y_down = false, track_forces = false;
  std::size_t smooth = kinematics::TrackForceOptions{}.half_window;
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
  // --ground alone is the surface level of --track-forces' penetration; with --radius it is
  // also the paper's geometric window criterion.
  if (o.radius && !o.ground)
    throw InputError("<command line>", 0, "--ground",
                     "the ground-level criterion needs both --ground Y and --radius R (m)");
  if (o.ground && !o.radius && !o.track_forces)
    throw InputError("<command line>", 0, "--radius",
                     "--ground needs --radius R (m) for the ground-level window criterion, or "
                     "--track-forces for the surface level of the track's penetration");
  if (o.radius) {
    opt.ground_y_m = o.ground;
    opt.contact_radius_m = o.radius;
  }
  if (!(o.k_sigma > 0)) throw InputError("<command line>", 0, "--k-sigma", "must be positive");
  opt.detection_k_sigma = o.k_sigma;
  opt.detection_guard_points = o.guard;
  return opt;
}

std::string release_id(const ReconstructCliOptions& o, const std::string& track) {
  return o.id.empty() ? fs::path(track).stem().string() : o.id;
}

/// One track's results.
struct Release {
  std::string track, id;
  kinematics::Track tracked;
  kinematics::Reconstruction r;
  std::optional<BlockTrack> forces;
  std::vector<std::string> figures;
};

// --track-forces: the block's mass and inertia from --mass / --inertia, else from --shape (the
// catalog's lab blocks or a shape file), whose geometry also gives the penetration.
kinematics::TrackForceOptions track_force_options(const ReconstructCliOptions& o,
                                                  const kinematics::ReconstructOptions& opt) {
  kinematics::TrackForceOptions f;
  f.half_window = o.smooth;
  f.gravity_mps2 = opt.gravity_mps2.value_or(f.gravity_mps2);
  f.surface_y_m = o.ground.value_or(0.0);
  std::optional<Shape> shape;
  if (!o.mass || !o.inertia || o.shape != "unknown") {
    if (o.shape == "unknown")
      throw InputError("<command line>", 0, "--shape",
                       "--track-forces needs the block: --shape (cylinder, triangle or a shape "
                       "file), or both --mass and --inertia");
    shape = Shape::resolve(o.shape);
  }
  f.mass_kg = o.mass ? *o.mass : shape->mass_kg;
  f.inertia_kgm2 = o.inertia ? *o.inertia : shape->inertia_kgm2;
  if (shape)
    f.depth_below_centroid_m = [s = *shape](double a) { return s.depth_below_centroid(a); };
  return f;
}

// The releases in the impact-set schema, with the standard errors as sigma columns, and with
// --track-forces their tracks (/dem/tracks/ID) in the same HDF5 file.
void write_releases(const ReconstructCliOptions& o, const std::vector<Release>& releases) {
  ImpactSet set;
  set.source =
      releases.size() == 1 ? releases[0].track : fs::path(releases[0].track).parent_path().string();
  for (const Release& rel : releases) {
    set.comments.push_back("ricochet reconstruct " + rel.track + " (window " + rel.r.window_method +
                           ")");
    set.impacts.push_back(kinematics::to_impact(rel.r, rel.id, o.shape));
  }
  write_impact_set(set, o.output.out);
  for (const Release& rel : releases)
    if (rel.forces) write_block_track(o.output.out, rel.id, *rel.forces);
}

/// Above this fraction of the contact window, one local fit's span blurs the force beyond its
/// standard errors: measured on filmed LIGGGHTS impacts (13 ms contacts), spans of 0.31 of the
/// contact keep the rms of z = error / s.e. at 0.9-1.1, spans of 0.6 raise it to 2.9-9
/// (docs/diagnosis.md, "Forces from video"; scripts/video-forces.sh).
constexpr double kBlurFraction = 1.0 / 3.0;

/// Summary of a release's force track for the text and JSON outputs.
struct ForceSummary {
  double span_s = 0, peak_fcy_N = 0, sigma_at_peak_N = 0, median_sigma_fcy_N = 0;
  double contact_s = 0;  ///< the reconstruction's contact window [s]
  bool blurred = false;  ///< span_s > kBlurFraction * contact_s
};

ForceSummary summarize_forces(const Release& rel, std::size_t k) {
  const BlockTrack& b = *rel.forces;
  ForceSummary s;
  std::vector<double> spans;
  std::size_t peak = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    spans.push_back(kinematics::smoothing_span_s(rel.tracked, i, k));
    if (b.fcy[i] > b.fcy[peak]) peak = i;
  }
  s.span_s = stats::robust_summarize(spans).median;
  s.median_sigma_fcy_N = stats::robust_summarize(b.sigma_fcy).median;  // NaN entries skipped
  s.peak_fcy_N = b.fcy[peak];
  s.sigma_at_peak_N = b.sigma_fcy[peak];
  s.contact_s = rel.r.contact_end_s - rel.r.contact_start_s;
  s.blurred = s.span_s > kBlurFraction * s.contact_s;
  return s;
}

/// The contact force and torque from the accelerations against time, with +-2 s.e. bands.
void draw_forces(const BlockTrack& b, const kinematics::Reconstruction& r, const std::string& title,
                 const std::string& path) {
  report::Figure fig;
  fig.title = "Contact force from the tracked accelerations of " + title;
  fig.width_px = 1350;
  fig.height_px = 420;
  struct Col {
    const std::vector<double>*v, *sd;
    const char *name, *unit;
  };
  const Col cols[3] = {{&b.fcx, &b.sigma_fcx, "fcx", "N"},
                       {&b.fcy, &b.sigma_fcy, "fcy", "N"},
                       {&b.torque, &b.sigma_torque, "torque", "N m"}};
  for (const Col& c : cols) {
    report::Panel p;
    p.title = std::string(c.name) + "(t)";
    p.xlabel = "t [s]";
    p.ylabel = std::string(c.name) + " [" + c.unit + "]";
    report::Series band;
    band.title = "+-2 s.e.";
    band.style = "filledcurves";
    band.color = report::colour::kGrey;
    report::Series line;
    line.title = "estimate";
    line.style = "linespoints";
    line.color = report::colour::kBlue;
    for (std::size_t i = 0; i < b.size(); ++i) {
      if (!std::isfinite((*c.v)[i])) continue;
      line.x.push_back(b.t[i]);
      line.y.push_back((*c.v)[i]);
      if (!std::isfinite((*c.sd)[i])) continue;
      band.x.push_back(b.t[i]);
      band.ylo.push_back((*c.v)[i] - 2 * (*c.sd)[i]);
      band.yhi.push_back((*c.v)[i] + 2 * (*c.sd)[i]);
      band.y.push_back((*c.v)[i]);
    }
    if (line.x.empty()) continue;
    if (!band.x.empty()) p.series.push_back(band);
    p.series.push_back(line);
    for (double t : {r.contact_start_s, r.contact_end_s}) {
      report::Series w;
      w.title = t == r.contact_start_s ? "contact window" : "";
      w.color = report::colour::kVermillion;
      const auto [lo, hi] = std::minmax_element(line.y.begin(), line.y.end());
      w.x = {t, t};
      w.y = {*lo, *hi};
      p.series.push_back(w);
    }
    fig.panels.push_back(p);
  }
  report::render(fig, path);
}

json result_json(const ReconstructCliOptions& o, const Release& rel,
                 const kinematics::ReconstructOptions& opt) {
  const kinematics::Reconstruction& r = rel.r;
  json doc;
  doc["command"] = "reconstruct";
  doc["source"] = rel.track;
  doc["id"] = rel.id;
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
  if (rel.forces) {
    const ForceSummary f = summarize_forces(rel, o.smooth);
    doc["track_forces"] = {{"half_window_frames", o.smooth},
                           {"span_s", f.span_s},
                           {"span_over_contact", f.span_s / f.contact_s},
                           {"blurred", f.blurred},
                           {"peak_fcy_N", f.peak_fcy_N},
                           {"sigma_at_peak_N", f.sigma_at_peak_N},
                           {"median_sigma_fcy_N", f.median_sigma_fcy_N},
                           {"track", std::string(kTracksGroup) + "/" + rel.id}};
  }
  doc["figures"] = rel.figures;
  doc["out"] = o.output.out.empty() ? json(nullptr) : json(o.output.out);
  return doc;
}

void print_text(const ReconstructCliOptions& o, const Release& rel,
                const kinematics::ReconstructOptions& opt) {
  const kinematics::Reconstruction& r = rel.r;
  std::cout << fmt::format(
      "{}: contact window [{:.5f}, {:.5f}] s ({}), {} points before, {} after\n", rel.track,
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
  if (rel.forces) {
    const ForceSummary f = summarize_forces(rel, o.smooth);
    std::cout << fmt::format(
        "  contact force from the accelerations ({}-frame fits, time resolution {:.1f} ms): "
        "peak fcy {:.0f} +- {:.0f} N (s.e.), median s.e. {:.0f} N\n",
        2 * o.smooth + 1, 1e3 * f.span_s, f.peak_fcy_N, f.sigma_at_peak_N, f.median_sigma_fcy_N);
    if (f.blurred)
      std::cout << fmt::format(
          "  warning: one fit spans {:.1f} ms, more than a third of the {:.1f} ms contact window: "
          "the force's shape is blurred beyond its standard errors (a higher frame rate or a "
          "smaller --smooth)\n",
          1e3 * f.span_s, 1e3 * f.contact_s);
  }
  for (const std::string& f : rel.figures) std::cout << "wrote " << f << "\n";
}

void check_options(const ReconstructCliOptions& o) {
  if (o.track_forces) {
    if (o.output.out.empty())
      throw InputError("<command line>", 0, "--track-forces",
                       "the track is written into the --out HDF5 file: give --out FILE.h5");
    require_out_extension(o.output, {".h5", ".hdf5"});
  } else {
    require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
    if (o.mass) throw InputError("<command line>", 0, "--mass", "only used with --track-forces");
    if (o.inertia)
      throw InputError("<command line>", 0, "--inertia", "only used with --track-forces");
  }
  if (o.sigma_position && !(*o.sigma_position > 0))
    throw InputError("<command line>", 0, "--sigma-position", "must be a positive length in m");
  if (o.tracks.size() > 1)
    for (const auto& [name, given] :
         {std::pair{"--id", !o.id.empty()}, std::pair{"--window", !o.window.empty()}})
      if (given)
        throw InputError("<command line>", 0, name,
                         "names one release's value; with several tracks each release's id is "
                         "its file name and its window is detected");
}

Release reconstruct_one(const ReconstructCliOptions& o, const std::string& path,
                        const kinematics::ReconstructOptions& opt) {
  Release rel;
  rel.track = path;
  rel.id = release_id(o, path);
  rel.tracked = kinematics::read_track_csv(path, o.pixel_size, o.y_down);
  if (o.sigma_position) rel.tracked.sigma_position_m = *o.sigma_position;
  try {
    rel.r = kinematics::reconstruct(rel.tracked, opt);
  } catch (const std::invalid_argument& e) {
    // Not enough free flight, no contact found...: the user's track or options are at fault.
    throw InputError(path, 0, "", e.what());
  }
  if (o.track_forces) {
    try {
      rel.forces = kinematics::track_with_forces(
          rel.tracked, rel.r.sigma_position_m, rel.r.sigma_theta_rad, track_force_options(o, opt));
    } catch (const std::invalid_argument& e) {
      throw InputError(path, 0, "--track-forces", e.what());
    }
  }
  if (!o.figures.empty()) {
    const std::string stem = fs::path(path).stem().string();
    rel.figures.push_back((fs::path(o.figures) / ("reconstruct_" + stem + ".svg")).string());
    draw(rel.tracked, rel.r, rel.figures.back());
    if (rel.forces) {
      rel.figures.push_back(
          (fs::path(o.figures) / ("reconstruct_forces_" + stem + ".svg")).string());
      draw_forces(*rel.forces, rel.r, rel.tracked.source, rel.figures.back());
    }
  }
  return rel;
}

void run(const ReconstructCliOptions& o) {
  check_options(o);
  const kinematics::ReconstructOptions opt = reconstruct_options(o);
  std::vector<Release> releases;
  std::map<std::string, std::string> seen;  // id -> track, for ids given twice
  for (const std::string& path : o.tracks) {
    releases.push_back(reconstruct_one(o, path, opt));
    const auto [it, fresh] = seen.emplace(releases.back().id, path);
    if (!fresh)
      throw InputError(path, 0, "TRACK",
                       "release id '" + it->first + "' is also the id of " + it->second +
                           " (ids are the file names without their extension)");
  }
  if (!o.output.out.empty()) write_releases(o, releases);
  if (o.output.json) {
    if (releases.size() == 1) {
      print_json(result_json(o, releases[0], opt));
      return;
    }
    json doc{{"command", "reconstruct"}, {"releases", json::array()}};
    for (const Release& rel : releases) doc["releases"].push_back(result_json(o, rel, opt));
    doc["out"] = o.output.out.empty() ? json(nullptr) : json(o.output.out);
    print_json(doc);
    return;
  }
  for (const Release& rel : releases) print_text(o, rel, opt);
  if (!o.output.out.empty())
    std::cout << fmt::format("wrote {} ({} release{})\n", o.output.out, releases.size(),
                             releases.size() == 1 ? "" : "s");
}

}  // namespace

void add_reconstruct_command(CLI::App& app) {
  auto o = std::make_shared<ReconstructCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "reconstruct",
      "Incident and reflected velocities of releases from their tracked points (paper section "
      "2.3): ballistic fits before and after the contact window, with standard errors");
  sub->add_option("TRACK", o->tracks,
                  "Track CSV(s), one release each: t[s], x, y, mark_x, mark_y (px, mm or m)")
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
  sub->add_option("--shape", o->shape,
                  "Block shape written by --out; with --track-forces the block (cylinder, "
                  "triangle or a shape file) whose mass, inertia and geometry are used")
      ->capture_default_str();
  sub->add_flag("--track-forces", o->track_forces,
                "Also write the track with the contact force and torque from the tracked "
                "accelerations (and their standard errors) into the --out HDF5 file");
  sub->add_option("--mass", o->mass, "Block mass [kg] for --track-forces (default: --shape's)");
  sub->add_option("--inertia", o->inertia,
                  "Moment of inertia about the centroid [kg m^2] for --track-forces (default: "
                  "--shape's)");
  sub->add_option("--smooth", o->smooth,
                  "Half window k of the local quadratic fits of --track-forces [frames]: each fit "
                  "spans 2k+1 frames")
      ->capture_default_str();
  add_figures_option(sub, o->figures, "an SVG of x(t), y(t), theta(t) and the fits");
  add_output_options(sub, o->output);
  check_range(sub, "--pixel-size", 1e-12, 1e3);
  check_range(sub, "--gravity", 0, 1e3);
  check_range(sub, "--radius", 1e-6, 1e3);
  check_range(sub, "--k-sigma", 1e-3, 1e3);
  check_range(sub, "--guard", 0, 1e6);
  check_range(sub, "--sigma-position", 1e-12, 1e3);
  check_range(sub, "--mass", 1e-6, 1e6);
  check_range(sub, "--inertia", 1e-9, 1e6);
  check_range(sub, "--smooth", 1, 50);
  sub->callback([o] { run(*o); });
}

}  // namespace ricochet::cli
