// `film_tracks`: a camera for simulated impacts, and the check of what it gives back.
//
//   film_tracks FILE.h5 OUT_DIR --radius R [--fps 400] [--noise-m 1e-3] [--seed 1]
//       films every /dem/tracks/ID of FILE (a LIGGGHTS campaign, the independent simulator...)
//       as a lab's camera would (truth_video.hpp): OUT_DIR/ID.csv with y measured from the bed
//       surface, which the track's penetration column gives for a disc of radius R [m] (the
//       surface = median of y - R + penetration over the records).
//   film_tracks --compare FILE.h5 VIDEO.h5 [--json]
//       VIDEO.h5 from `ricochet reconstruct OUT_DIR/*.csv --track-forces`: the force estimated
//       from the film against the force FILE recorded, at the film's frames while the recorded
//       force bears (above 0.2 x the block's weight), the recorded force scaled to the video's
//       block (a slab carries a fraction of it): rms error, the stated standard errors, the rms
//       of z = error / s.e., the fraction within +-2 s.e., and the ratio of peak forces.
// Used by scripts/video-forces.sh (docs/diagnosis.md, "Forces from video"). Exit codes: 0 ok,
// 1 runtime failure, 2 bad option.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <vector>

#include "impact/block_track.hpp"
#include "stats/robust.hpp"
#include "stats/track_summary.hpp"
#include "truth_video.hpp"

using namespace ricochet;

namespace {

double median(const std::vector<double>& v) {
  return stats::robust_summarize(v).median;
}

// Linear interpolation of column c of track h at time t (inside h's records).
double at(const BlockTrack& h, const std::vector<double>& c, double t) {
  const auto it = std::upper_bound(h.t.begin(), h.t.end(), t);
  if (it == h.t.begin()) return c.front();
  if (it == h.t.end()) return c.back();
  const std::size_t j = static_cast<std::size_t>(it - h.t.begin());
  const double s = (t - h.t[j - 1]) / (h.t[j] - h.t[j - 1]);
  return (1 - s) * c[j - 1] + s * c[j];
}

int film(const std::string& file, const std::string& dir, double radius,
         const truth::VideoOptions& video, std::uint64_t seed) {
  const auto ids = block_track_ids(file);
  if (ids.empty()) {
    std::cerr << "film_tracks: " << file << " has no /dem/tracks\n";
    return 2;
  }
  std::filesystem::create_directories(dir);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    BlockTrack h = read_block_track(file, ids[i]);
    h.pad();
    std::vector<double> surface;
    for (std::size_t k = 0; k < h.size(); ++k)
      if (std::isfinite(h.penetration[k])) surface.push_back(h.y[k] - radius + h.penetration[k]);
    const double y0 = median(surface);
    if (!std::isfinite(y0)) {
      std::cerr << "film_tracks: " << file << ": /dem/tracks/" << ids[i]
                << " has no penetration column to place the surface\n";
      return 2;
    }
    for (double& y : h.y) y -= y0;
    std::ofstream(std::filesystem::path(dir) / (ids[i] + ".csv"))
        << truth::video_csv(h, video, seed * 1000003ULL + i);
  }
  std::cout << fmt::format("filmed {} tracks of {} into {} ({:g} fps, noise {:g} m)\n", ids.size(),
                           file, dir, video.fps, video.noise_m);
  return 0;
}

int compare(const std::string& file, const std::string& video_file, bool as_json) {
  std::vector<double> err2, se, z, peak_ratio;
  std::size_t releases = 0;
  const auto source_ids = block_track_ids(file);
  for (const std::string& id : block_track_ids(video_file)) {
    if (std::find(source_ids.begin(), source_ids.end(), id) == source_ids.end()) continue;
    BlockTrack rec = read_block_track(file, id), vid = read_block_track(video_file, id);
    rec.pad();
    vid.pad();
    double m_rec = rec.block_mass_kg;
    if (!std::isfinite(m_rec)) m_rec = stats::free_flight_mass_kg(rec);
    const double scale = vid.block_mass_kg / m_rec;
    const double bearing = 0.2 * m_rec * 9.81;
    double peak_rec = 0, peak_vid = 0;
    for (double f : rec.fcy) peak_rec = std::max(peak_rec, scale * f);
    for (std::size_t k = 0; k < vid.size(); ++k) {
      const double t = vid.t[k];
      if (t < rec.t.front() || t > rec.t.back()) continue;
      const double f = at(rec, rec.fcy, t);
      if (!(f > bearing)) continue;
      peak_vid = std::max(peak_vid, vid.fcy[k]);
      const double e = vid.fcy[k] - scale * f;
      err2.push_back(e * e);
      se.push_back(vid.sigma_fcy[k]);
      z.push_back(e / vid.sigma_fcy[k]);
    }
    if (peak_rec > 0) peak_ratio.push_back(peak_vid / peak_rec);
    ++releases;
  }
  if (z.empty()) {
    std::cerr << "film_tracks: no frame of " << video_file << " falls in a contact of " << file
              << "\n";
    return 2;
  }
  double sz2 = 0, e2 = 0;
  std::size_t inside = 0;
  for (std::size_t k = 0; k < z.size(); ++k) {
    sz2 += z[k] * z[k];
    e2 += err2[k];
    inside += std::abs(z[k]) <= 2;
  }
  const double n = static_cast<double>(z.size());
  nlohmann::json doc{{"source", file},
                     {"video", video_file},
                     {"releases", releases},
                     {"contact_frames", z.size()},
                     {"rms_error_fcy_N", std::sqrt(e2 / n)},
                     {"median_se_fcy_N", median(se)},
                     {"rms_z", std::sqrt(sz2 / n)},
                     {"within_2se", static_cast<double>(inside) / n},
                     {"median_peak_ratio", median(peak_ratio)}};
  if (as_json) {
    std::cout << doc.dump() << "\n";
    return 0;
  }
  std::cout << fmt::format(
      "{} releases, {} contact frames: fcy rms error {:.0f} N, median s.e. {:.0f} N, rms z "
      "{:.2f}, {:.0f} % within 2 s.e., peak ratio (video / recorded) {:.2f}\n",
      releases, z.size(), doc["rms_error_fcy_N"].get<double>(),
      doc["median_se_fcy_N"].get<double>(), doc["rms_z"].get<double>(),
      100 * doc["within_2se"].get<double>(), doc["median_peak_ratio"].get<double>());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Film simulated impacts as a lab camera would, or compare the forces back"};
  std::string file, dir, compare_with;
  double radius = 0;
  truth::VideoOptions video;
  std::uint64_t seed = 1;
  bool as_json = false;
  app.add_option("FILE", file, "Impact set with /dem/tracks (.h5)")->required();
  app.add_option("OUT_DIR", dir, "Folder of the films (one CSV per track)");
  app.add_option("--radius", radius, "Radius of the (disc) block [m], to place the surface");
  app.add_option("--fps", video.fps, "Frames per second, in [50, 1e5]")->capture_default_str();
  app.add_option("--noise-m", video.noise_m, "Pointing noise, sd of each coordinate [m]")
      ->capture_default_str();
  app.add_option("--seed", seed, "Seed of the noise and the frames' phase")->capture_default_str();
  app.add_option("--compare", compare_with, "VIDEO.h5: compare its forces with FILE's");
  app.add_flag("--json", as_json, "One JSON line (with --compare)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (!compare_with.empty()) return compare(file, compare_with, as_json);
    if (dir.empty() || !(radius > 0)) {
      std::cerr << "film_tracks: give OUT_DIR and --radius R > 0 (or --compare VIDEO.h5)\n";
      return 2;
    }
    if (!(video.fps >= 50 && video.fps <= 1e5) || !(video.noise_m >= 0)) {
      std::cerr << "film_tracks: --fps outside [50, 1e5] or --noise-m negative\n";
      return 2;
    }
    return film(file, dir, radius, video, seed);
  } catch (const std::exception& e) {
    std::cerr << "film_tracks: " << e.what() << "\n";
    return 1;
  }
}
