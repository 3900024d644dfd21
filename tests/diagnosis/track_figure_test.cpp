// The report's contact figure (diagnosis/track_figure.hpp) on a shipped campaign that keeps its
// tracks (data/resolved/lab-cylinders.h5: a 0.06 m slab, 12-column tracks without a block mass)
// and on one that does not: which impact, the scaling of the slab's force to the lab block, the
// common time origin, the reduced law's curves, and rendering through gnuplot.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "diagnosis/track_figure.hpp"
#include "impact/block_track.hpp"
#include "stats/track_summary.hpp"

namespace ricochet::diagnosis {
namespace {

namespace fs = std::filesystem;
const std::string kResolved = std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/";

double max_of(const std::vector<double>& v) {
  double m = -INFINITY;
  for (double x : v)
    if (std::isfinite(x)) m = std::max(m, x);
  return m;
}

TEST(TrackFigure, LiggghtsBesideTheReducedLawScaledToTheLabBlock) {
  const std::string data = kResolved + "lab-cylinders.h5";
  const ImpactSet set = read_impact_set(data);
  const Model model = Model::paper();
  const auto f = contact_track_figure(data, set, Shape::cylinder(), model, {},
                                      bulk_engine_options(), "C03", "lab cylinders");
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->stem, "contact-track-C03");  // the preferred release, which has a track
  ASSERT_EQ(f->figure.panels.size(), 3u);
  const auto& normal = f->figure.panels[0].series;
  ASSERT_EQ(normal.size(), 3u);  // LIGGGHTS, the reduced law, the impact's end

  // The slab is 0.06 m of the 0.29 m cylinder: 2.876 kg, read from the track's free flight (the
  // file has no block mass), so its force is multiplied by 13.9 / 2.876 = 4.833.
  const BlockTrack track = read_block_track(data, "C03");
  const stats::TrackSummary dem = stats::summarize_track(track, "C03");
  EXPECT_NEAR(dem.block_mass_kg, 13.9 * 0.06 / 0.29, 0.01);
  EXPECT_NEAR(max_of(normal[0].y), dem.peak_normal_force_N * 13.9 / dem.block_mass_kg, 1e-6);
  EXPECT_NE(f->caption.find("from the track's free flight"), std::string::npos) << f->caption;
  // The impact's end: a vertical line at the first record after the peak whose force is at most
  // the slab block's weight, on the figure's time axis (ms from the contact's start).
  ASSERT_TRUE(std::isfinite(dem.impact_duration_s));
  const auto& end = normal[2];
  ASSERT_EQ(end.x.size(), 2u);
  EXPECT_EQ(end.x[0], end.x[1]);
  EXPECT_NEAR(end.x[0], 1e3 * dem.impact_duration_s, 1e-9);
  const auto at = std::find_if(normal[0].x.begin(), normal[0].x.end(),
                               [&](double x) { return std::abs(x - end.x[0]) < 1e-9; });
  ASSERT_NE(at, normal[0].x.end());
  EXPECT_LE(*(normal[0].y.begin() + (at - normal[0].x.begin())), 13.9 * 9.81 + 1e-9);
  EXPECT_NE(f->caption.find("The impact proper"), std::string::npos) << f->caption;
  // Time zero at the contact's start: the force there is above 0.2 of the slab block's weight,
  // and the record before it is not.
  const auto& t = normal[0].x;
  const auto zero = std::find(t.begin(), t.end(), 0.0);
  ASSERT_NE(zero, t.end());
  const std::size_t k = static_cast<std::size_t>(zero - t.begin());
  ASSERT_GT(k, 0u);
  const double threshold = 0.2 * 13.9 * 9.81;  // 0.2 x the weight, scaled like the force
  EXPECT_GT(std::hypot(normal[0].y[k], f->figure.panels[1].series[0].y[k]), threshold);
  EXPECT_LT(std::hypot(normal[0].y[k - 1], f->figure.panels[1].series[0].y[k - 1]), threshold);

  // The reduced law: a contact from t = 0 with a positive peak, and a penetration that comes
  // back to 0 when the block leaves.
  EXPECT_GT(normal[1].x.size(), 10u);
  EXPECT_LE(normal[1].x.size(), 401u);
  EXPECT_GT(max_of(normal[1].y), 0.0);
  const auto& h = f->figure.panels[2].series[1].y;
  EXPECT_GT(max_of(h), 0.0);
  EXPECT_LT(h.back(), 0.1 * max_of(h));

  const fs::path svg =
      fs::temp_directory_path() / ("ricochet-track-figure-" + std::to_string(::getpid()) + ".svg");
  report::render(f->figure, svg.string());
  EXPECT_GT(fs::file_size(svg), 5000u);
  fs::remove(svg);
}

TEST(TrackFigure, NoneForAFileWithoutTracksOrAnUnknownPreference) {
  const std::string without = kResolved + "lab-cylinders-rolling-gb-ground.h5";
  EXPECT_FALSE(contact_track_figure(without, read_impact_set(without), Shape::cylinder(),
                                    Model::paper(), {}, bulk_engine_options(), "", "x")
                   .has_value());
  // A preference the set does not have falls back to its first release with a track.
  const std::string data = kResolved + "lab-cylinders.h5";
  const auto f = contact_track_figure(data, read_impact_set(data), Shape::cylinder(),
                                      Model::paper(), {}, bulk_engine_options(), "nope", "x");
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->stem, "contact-track-C01");
}

}  // namespace
}  // namespace ricochet::diagnosis
