// The main job's validation report (results/report.html, written by ./run.sh main and by the
// quick main job that ./run.sh test runs before ctest), read as a reviewer would (issue 13):
// under 3 MB, every set opening with its verdict sentence and its ladder figure, every LIGGGHTS
// campaign with a picture of one impact, the current calibration's verification in two halves
// against the lab, and in headless Chromium every figure shown with drawn
// content and no legend inside a plot area; a screenshot is kept under the build folder.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "report/html.hpp"
#include "support/chromium.hpp"
#include "support/program_test.hpp"

namespace ricochet {
namespace {

namespace fs = std::filesystem;

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto k = text.find(what); k != std::string::npos; k = text.find(what, k + 1)) ++n;
  return n;
}

// The probe's legend check can fail: a gnuplot figure with its key inside the plot (which the
// report's plot layer refuses to draw, tests/report/plot_test.cpp), embedded as the report
// embeds figures, is caught; the same figure with the key outside is not.
TEST(MainJobReport, TheLegendCheckCatchesAKeyInsideThePlot) {
  if (test::chromium_missing()) GTEST_SKIP() << "no /usr/bin/chromium (apt install chromium)";
  const fs::path dir = fs::temp_directory_path() / "ricochet-legend-probe";
  fs::create_directories(dir);
  for (const std::string key : {"top left", "outside right top"}) {
    const fs::path svg = dir / "figure.svg";
    const std::string cmd =
        "gnuplot -e " +
        test::quote("set terminal svg size 640,480; set output '" + svg.string() + "'; set key " +
                    key + "; plot x title 'line', x**2 title 'square'");
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    const std::string b64 = report::base64(test::slurp(svg));  // as the report embeds it
    const fs::path html = dir / "page.html";
    std::ofstream(html) << "<html><body><img src=\"data:image/svg+xml;base64," << b64
                        << "\"></body></html>";
    const test::RenderedFigures shown = test::render_in_chromium(html, dir);
    ASSERT_EQ(shown.total, 1) << key;
    EXPECT_EQ(shown.legend_entries, 2) << key;
    EXPECT_EQ(shown.overlapping.size(), key == "top left" ? 2u : 0u) << key;
  }
  fs::remove_all(dir);
}

// The page is mailed around: it names the files it read as data/... or relative to where it ran
// (shown_path), never by the folders of the machine that wrote it.
TEST(MainJobReport, NamesItsFilesWithoutThisMachinesFolders) {
  const fs::path html = fs::path(RICOCHET_SOURCE_DIR) / "results" / "report.html";
  if (!fs::exists(html)) GTEST_SKIP() << "no " << html << ": run ./run.sh main or ./run.sh test";
  const std::string page = test::slurp(html);
  const std::string root = fs::weakly_canonical(RICOCHET_SOURCE_DIR).string() + "/";
  EXPECT_EQ(count(page, root), 0) << "the page names files under " << root;
  EXPECT_GT(count(page, "data/lab/cylinders.csv"), 0);
}

TEST(MainJobReport, ReadsAsAReviewerWouldInChromium) {
  const fs::path html = fs::path(RICOCHET_SOURCE_DIR) / "results" / "report.html";
  if (!fs::exists(html))
    GTEST_SKIP() << "no " << html << ": run ./run.sh main (or ./run.sh test, whose quick main job "
                 << "writes it before ctest runs)";
  if (test::chromium_missing())
    GTEST_SKIP() << "no /usr/bin/chromium: the report is not rendered (apt install chromium)";
  EXPECT_LE(fs::file_size(html), 3'000'000u) << "the page is mailed around: 3 MB at most";
  const std::string page = test::slurp(html);

  // Each set's section: its verdict sentence first, its ladder figure, and for a LIGGGHTS
  // campaign the picture of one impact.
  const std::regex heading("<h2 id=\"set[0-9]+\">([^<]*)");
  std::vector<std::pair<std::string, std::size_t>> sets;
  for (auto it = std::sregex_iterator(page.begin(), page.end(), heading);
       it != std::sregex_iterator(); ++it)
    sets.emplace_back((*it)[1].str(), static_cast<std::size_t>(it->position()));
  ASSERT_GE(sets.size(), 2u) << "the main job reports the lab cylinders and a LIGGGHTS set";
  // The current calibration's verification (issue 32, item 5): its held-out half, against the
  // lab's releases of the same ids, and its calibration half beside it.
  int verification_halves = 0;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    const std::size_t end = k + 1 < sets.size() ? sets[k + 1].second : page.size();
    const std::string section = page.substr(sets[k].second, end - sets[k].second);
    const std::string& label = sets[k].first;
    if (label.find("sand-only recalibration") != std::string::npos &&
        (label.find("held-out half") != std::string::npos ||
         label.find("calibration half") != std::string::npos)) {
      ++verification_halves;
      EXPECT_NE(label.find("not on a stiffness plateau"), std::string::npos) << label;
      EXPECT_NE(section.find("those this set was run at"), std::string::npos)
          << label << ": not compared with the lab's releases of its own ids";
    }
    const auto verdict = section.find("<p class=\"verdict\">");
    ASSERT_NE(verdict, std::string::npos) << label << ": no verdict sentence";
    EXPECT_LT(verdict, section.find("<details>")) << label << ": the verdict is not first";
    EXPECT_EQ(count(section, "alt=\"Each rung adds one effect"), 1) << label << ": ladder figure";
    if (label.find("LIGGGHTS") != std::string::npos) {
      // The picture of the bed, once per file (a file given twice, the verification's two
      // halves, points the second section to the first's), and, when the file keeps its tracks,
      // the impact in time (the main job's own campaign does; shipped files of older campaigns
      // may not).
      const int pictures =
          count(section, "alt=\"One impact of this campaign (LIGGGHTS), side view");
      const int pointers = count(section, "first impact, through the contact, is pictured in");
      EXPECT_EQ(pictures + pointers, 1) << label << ": no picture of an impact, nor a pointer";
      EXPECT_LE(count(section, "alt=\"One impact of this campaign in time"), 1) << label;
      if (label.find("LIGGGHTS campaign") == 0) {
        EXPECT_EQ(count(section, "alt=\"One impact of this campaign in time"), 1)
            << label << ": the main job's campaign keeps its tracks, no contact in time";
      }
    }
  }

  EXPECT_EQ(verification_halves, 2)
      << "the report lacks a half of the sand recalibration's verification";

  const fs::path dir = fs::temp_directory_path() / "ricochet-main-job-report";
  fs::create_directories(dir);
  const test::RenderedFigures shown = test::render_in_chromium(html, dir);
  ASSERT_GE(shown.total, 10) << "the probe did not run in Chromium, or the page lost its figures";
  EXPECT_EQ(shown.shown, shown.total) << "some figures did not render";
  ASSERT_EQ(shown.ink.size(), static_cast<std::size_t>(shown.total));
  for (std::size_t k = 0; k < shown.ink.size(); ++k)
    EXPECT_GT(shown.ink[k], 0.01) << "figure " << k + 1 << " is blank";
  EXPECT_GT(shown.legend_entries, 20) << "too few legends found: the check would be vacuous";
  for (const auto& entry : shown.overlapping) ADD_FAILURE() << "legend inside a plot: " << entry;
  const fs::path png = test::screenshot(html, dir, "main-job-report-top.png");
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 20000u) << "the screenshot is (nearly) blank";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ricochet
