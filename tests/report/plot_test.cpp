// Figures through the real gnuplot: series counts in the SVG, literal titles with quotes, NaN
// breaks, empty series and panels, and clear errors when gnuplot is missing or fails.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <set>
#include <sstream>

#include "report/plot.hpp"

namespace ricochet {
namespace {

namespace fs = std::filesystem;
using report::Figure;
using report::Panel;
using report::Series;

class Plot : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ricochet-plot-test-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    ::unsetenv("RICOCHET_GNUPLOT");
  }
  void TearDown() override {
    ::unsetenv("RICOCHET_GNUPLOT");
    fs::remove_all(dir_);
  }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  /// gnuplot's SVG terminal wraps every plotted series in <g id="gnuplot_plot_<n><panel>">
  /// (an opaque legend repeats them, hence distinct ids).
  static int series_count(const std::string& svg) {
    std::set<std::string> ids;
    const std::string tag = "<g id=\"gnuplot_plot_";
    for (auto p = svg.find(tag); p != std::string::npos; p = svg.find(tag, p + 1))
      ids.insert(svg.substr(p + tag.size(), svg.find('"', p + tag.size()) - p - tag.size()));
    return static_cast<int>(ids.size());
  }
  static Series line(const std::string& title, int n, double slope) {
    Series s;
    s.title = title;
    for (int i = 0; i < n; ++i) {
      s.x.push_back(i);
      s.y.push_back(slope * i);
    }
    return s;
  }
  fs::path dir_;
};

TEST_F(Plot, GridOfPanelsWithTheExpectedNumberOfSeries) {
  Figure f;
  f.title = "three panels";
  f.columns = 2;
  Panel a, b, c;
  a.series = {line("a1", 10, 1), line("a2", 10, 2)};
  b.series = {line("b1", 10, -1)};
  b.series[0].style = "points";
  c.series = {line("c1", 5, 1), line("c2", 5, 2), line("c3", 5, 3)};
  c.series[1].style = "steps";
  c.series[2].style = "errorbars";
  c.series[2].ylo = {0, 1, 2, 3, 4};
  c.series[2].yhi = {1, 2, 3, 4, 5};
  c.key = "outside right top box";
  f.panels = {a, b, c};
  const fs::path out = dir_ / "sub" / "grid.svg";  // parent created on demand
  report::render(f, out.string());
  const std::string svg = slurp(out);
  ASSERT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_EQ(series_count(svg), 6);
  EXPECT_NE(svg.find("three panels"), std::string::npos);
}

// The x tick labels of narrow panels do not run together: six panels side by side in 1,200 px
// (200 px each) over x in [0.5, 0.9] get at most 4 labels each, where gnuplot alone put 9 (0.5,
// 0.55, ..., 0.9) and the abacus of calibrate-grains was unreadable; one wide panel keeps more.
TEST_F(Plot, NarrowPanelsGetFewerXTickLabels) {
  // The numeric labels in [0, 1.5] of an SVG: the x ticks (the y data lie in 100..200).
  const auto x_labels = [](const std::string& svg) {
    int n = 0;
    const std::regex text("<text>\\s*([-0-9.]+)\\s*<");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), text); it != std::sregex_iterator();
         ++it) {
      const double v = std::stod((*it)[1].str());
      if (v >= 0 && v <= 1.5) ++n;
    }
    return n;
  };
  Series s;
  for (int i = 0; i <= 40; ++i) {
    s.x.push_back(0.5 + 0.01 * i);
    s.y.push_back(100 + 2.5 * i);
  }
  Panel p;
  p.series = {s};
  Figure narrow;
  narrow.columns = 6;
  narrow.width_px = 1200;
  narrow.panels.assign(6, p);
  report::render(narrow, (dir_ / "narrow.svg").string());
  const int per_panel = x_labels(slurp(dir_ / "narrow.svg")) / 6;
  EXPECT_GE(per_panel, 2);
  EXPECT_LE(per_panel, 4);
  Figure wide;
  wide.columns = 1;
  wide.width_px = 1200;
  wide.panels = {p};
  report::render(wide, (dir_ / "wide.svg").string());
  EXPECT_GE(x_labels(slurp(dir_ / "wide.svg")), 5);
}

TEST_F(Plot, TitlesWithQuotesAndUnderscoresArePrintedLiterally) {
  Figure f;
  Panel p;
  p.title = "operator's \"best\" V_in^x";
  p.xlabel = "it's x";
  p.series = {line("don't", 4, 1)};
  f.panels = {p};
  const fs::path out = dir_ / "quotes.svg";
  report::render(f, out.string());
  const std::string svg = slurp(out);
  EXPECT_EQ(series_count(svg), 1);
  // gnuplot escapes XML itself; the characters arrive unchanged (no enhanced-text markup).
  EXPECT_NE(svg.find("V_in^x"), std::string::npos);
  EXPECT_NE(svg.find("don't"), std::string::npos);
  EXPECT_NE(svg.find("operator's"), std::string::npos);
}

TEST_F(Plot, NanBreaksLinesAndEmptySeriesKeepTheirLegend) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Figure f;
  Panel p;
  Series broken = line("broken", 6, 1);
  broken.y[2] = nan;
  broken.x[4] = std::numeric_limits<double>::infinity();
  Series empty;
  empty.title = "nothing";
  Series all_nan;
  all_nan.title = "all nan";
  all_nan.x = {1, 2};
  all_nan.y = {nan, nan};
  p.series = {broken, empty, all_nan};
  Panel blank;  // a panel without any data still renders
  blank.title = "blank";
  blank.series = {empty};
  f.panels = {p, blank};
  const fs::path out = dir_ / "nan.svg";
  report::render(f, out.string());
  const std::string svg = slurp(out);
  // broken, nothing, all nan; the blank panel: an invisible placeholder (gnuplot needs one
  // drawable curve per panel) and nothing.
  EXPECT_EQ(series_count(svg), 5);
  EXPECT_NE(svg.find("nothing (no data)"), std::string::npos);
  EXPECT_NE(svg.find("all nan (no data)"), std::string::npos);
}

TEST_F(Plot, LogAxesDropNonPositivePoints) {
  Figure f;
  Panel p;
  p.logy = true;
  Series s = line("log", 5, 1);  // y[0] = 0 cannot be drawn on a log axis
  p.series = {s};
  f.panels = {p};
  const fs::path out = dir_ / "log.svg";
  report::render(f, out.string());
  EXPECT_EQ(series_count(slurp(out)), 1);
}

TEST_F(Plot, EcdfPanelIsAStaircaseFromZeroToOne) {
  const Panel p =
      report::ecdf_panel("ecdf", "v [m/s]", {{"a", {3.0, 1.0, 2.0, std::nan("")}}, {"b", {5.0}}});
  ASSERT_EQ(p.series.size(), 2u);
  EXPECT_EQ(p.series[0].style, "steps");
  EXPECT_EQ(p.series[0].x, (std::vector<double>{1, 1, 2, 3}));
  EXPECT_EQ(p.series[0].y, (std::vector<double>{0, 1.0 / 3, 2.0 / 3, 1}));
  EXPECT_EQ(p.series[1].y, (std::vector<double>{0, 1}));
  Figure f;
  f.panels = {p};
  const fs::path out = dir_ / "ecdf.svg";
  report::render(f, out.string());
  EXPECT_EQ(series_count(slurp(out)), 2);
}

TEST_F(Plot, MissingGnuplotIsAClearError) {
  ::setenv("RICOCHET_GNUPLOT", "/nonexistent/gnuplot", 1);
  Figure f;
  Panel p;
  p.series = {line("a", 3, 1)};
  f.panels = {p};
  const fs::path out = dir_ / "missing.svg";
  try {
    report::render(f, out.string());
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("gnuplot-nox"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(Plot, FailingGnuplotIsAClearErrorAndLeavesNoFile) {
  ::setenv("RICOCHET_GNUPLOT", "false", 1);  // exits with status 1
  Figure f;
  Panel p;
  p.series = {line("a", 3, 1)};
  f.panels = {p};
  const fs::path out = dir_ / "failed.svg";
  try {
    report::render(f, out.string());
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("gnuplot failed (exit status 1)"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(Plot, InconsistentFiguresAreRefusedBeforeCallingGnuplot) {
  Figure f;
  EXPECT_THROW(report::render(f, (dir_ / "x.svg").string()), std::invalid_argument);
  Panel p;
  Series s = line("a", 3, 1);
  s.y.pop_back();
  p.series = {s};
  f.panels = {p};
  EXPECT_THROW(report::render(f, (dir_ / "x.svg").string()), std::invalid_argument);
  f.panels[0].series = {line("a", 3, 1)};
  f.panels[0].series[0].style = "bars";
  EXPECT_THROW(report::render(f, (dir_ / "x.svg").string()), std::invalid_argument);
  f.panels[0].series[0].style = "lines";
  f.panels[0].series[0].color = "red' ; system 'touch pwned";
  EXPECT_THROW(report::render(f, (dir_ / "x.svg").string()), std::invalid_argument);
  f.panels[0].series[0].color = "";
  f.panels[0].key = "top; system";
  EXPECT_THROW(report::render(f, (dir_ / "x.svg").string()), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir_ / "x.svg"));
}

// The one figure style: automatic colours follow the Okabe-Ito sequence (colour-blind-safe), so
// the second series of a panel is orange, not gnuplot's default green.
TEST_F(Plot, AutomaticColoursAreOkabeIto) {
  Figure f;
  Panel p;
  p.series = {line("first", 5, 1), line("second", 5, 2)};
  f.panels = {p};
  const fs::path out = dir_ / "colours.svg";
  report::render(f, out.string());
  const std::string svg = slurp(out);
  EXPECT_NE(svg.find("rgb(230, 159,   0)"), std::string::npos) << "no Okabe-Ito orange";
  EXPECT_EQ(svg.find("rgb(  0, 158, 115)"), std::string::npos)
      << "gnuplot's default second colour is used";
}

// The .png extension gives a PNG of the figure's size (its IHDR chunk), and discs coloured by a
// value (the impact picture's style) render; other extensions and discs without radii are
// refused before gnuplot runs.
TEST_F(Plot, PngOfTheRequestedSizeAndDiscsColouredByValue) {
  Figure f;
  f.width_px = 640;
  f.height_px = 360;
  Panel p;
  Series discs;
  discs.style = "circles";
  discs.x = {0, 1, 2};
  discs.y = {0, 1, 0};
  discs.radius = {0.2, 0.3, 0.4};
  discs.value = {0.0, 1.0, 2.0};
  p.series = {discs};
  p.equal_aspect = true;
  p.cblabel = "speed [m/s]";
  p.cbmin = 0;
  p.cbmax = 2;
  f.panels = {p};
  const fs::path png = dir_ / "discs.png";
  report::render(f, png.string());
  const std::string bytes = slurp(png);
  ASSERT_GE(bytes.size(), 24u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n"));
  const auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
  };
  EXPECT_EQ(be32(16), 640u);
  EXPECT_EQ(be32(20), 360u);
  EXPECT_THROW(report::render(f, (dir_ / "discs.pdf").string()), std::invalid_argument);
  f.panels[0].series[0].radius.pop_back();
  EXPECT_THROW(report::render(f, (dir_ / "bad.png").string()), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir_ / "bad.png"));
}

// No legend covers data: every legend is placed outside the plot's border, even when the points
// fill the whole plot area; a legend inside the plot is refused.
TEST_F(Plot, LegendsLieOutsideThePlotArea) {
  Figure f;
  Panel p;
  Series cloud;
  cloud.title = "cloud";
  cloud.style = "points";
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      cloud.x.push_back(i);
      cloud.y.push_back(j);
    }
  p.series = {cloud, line("diagonal", 21, 1)};
  f.panels = {p};
  for (const std::string key : {"", "outside right top"}) {
    f.panels[0].key = key;
    const fs::path out = dir_ / "legend.svg";
    report::render(f, out.string());
    const std::string svg = slurp(out);
    // The plot's border: gnuplot's closed rectangle 'M x0,y0 L x0,y1 L x1,y1 L x1,y0 L x0,y0 Z'.
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        svg, m,
        std::regex(
            R"re(d='M([0-9.]+),([0-9.]+) L[0-9.]+,([0-9.]+) L([0-9.]+),[0-9.]+ L[0-9.]+,[0-9.]+ L[0-9.]+,[0-9.]+ Z)re")));
    const double x0 = std::stod(m[1]), y0 = std::stod(m[2]), y1 = std::stod(m[3]),
                 x1 = std::stod(m[4]);
    // Each legend entry: the translate() of the group holding its <text>TITLE</text>.
    for (const char* title : {"cloud", "diagonal"}) {
      ASSERT_TRUE(std::regex_search(
          svg, m,
          std::regex(std::string(R"re(translate\(([0-9.]+),([0-9.]+)\)[^>]*>\s*<text>)re") + title +
                     "</text>")))
          << title;
      const double x = std::stod(m[1]), y = std::stod(m[2]);
      const bool inside = x > std::min(x0, x1) && x < std::max(x0, x1) && y > std::min(y0, y1) &&
                          y < std::max(y0, y1);
      EXPECT_FALSE(inside) << "legend '" << title << "' at (" << x << ", " << y
                           << ") inside the plot [" << x0 << ", " << x1 << "] x [" << y0 << ", "
                           << y1 << "] with key '" << key << "'";
    }
  }
  f.panels[0].key = "top left";
  EXPECT_THROW(report::render(f, (dir_ / "inside.svg").string()), std::invalid_argument);
}

}  // namespace
}  // namespace ricochet
