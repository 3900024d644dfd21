// Test support: a page rendered by headless Chromium, as a reader sees it (tests of the HTML
// report). Skip the test when /usr/bin/chromium is absent (chromium_missing()).
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/program_test.hpp"

namespace ricochet::test {

inline bool chromium_missing() {
  return !std::filesystem::exists("/usr/bin/chromium");
}

/// What the probe measured in the rendered page.
struct RenderedFigures {
  int total = -1;                        ///< <img> elements
  int shown = -1;                        ///< decoded with a non-zero size on the page
  std::vector<double> ink;               ///< per image, the share of non-background pixels
  int legend_entries = -1;               ///< legend entries found in the SVG figures
  std::vector<std::string> overlapping;  ///< "figure index: entry" of legends inside a plot area
};

/// Runs headless Chromium on `html` with a script that, once the page has loaded:
/// - counts the images that decoded with a non-zero size;
/// - draws each on a canvas and measures the share of its pixels that are not background (white
///   or transparent);
/// - in each SVG figure (gnuplot's), finds every plot border (the closed rectangle
///   'M x0,y0 L x0,y1 L x1,y1 L x1,y0 L x0,y0 Z') and every legend entry (the translate() of the
///   first text of a 'gnuplot_plot_*' group), and lists the entries that lie inside a plot area,
///   where they could cover a plotted point (points are clipped to the border).
/// Returns the measurements, parsed from the dumped DOM; total = -1 if the probe did not run.
inline RenderedFigures render_in_chromium(const std::filesystem::path& html,
                                          const std::filesystem::path& dir) {
  std::string page = slurp(html);
  const std::string probe = R"JS(<script>window.addEventListener('load', function () {
  var imgs = document.images, ok = 0, ink = [], keys = 0, bad = [];
  for (var i = 0; i < imgs.length; i++) {
    var im = imgs[i], r = im.getBoundingClientRect();
    if (im.complete && im.naturalWidth > 0 && r.width > 0 && r.height > 0) ok++;
    var c = document.createElement('canvas');
    c.width = im.naturalWidth; c.height = im.naturalHeight;
    var g = c.getContext('2d'); g.drawImage(im, 0, 0);
    var px = g.getImageData(0, 0, c.width, c.height).data, n = 0;
    for (var k = 0; k < px.length; k += 4)
      if (px[k + 3] > 0 && (px[k] < 235 || px[k + 1] < 235 || px[k + 2] < 235)) n++;
    ink.push((n / (c.width * c.height)).toFixed(4));
    var head = 'data:image/svg+xml;base64,';
    if (im.src.indexOf(head) != 0) continue;
    var s = atob(im.src.substring(head.length)), m, B = [];
    var rb = /d='M([0-9.]+),([0-9.]+) L[0-9.]+,([0-9.]+) L([0-9.]+),[0-9.]+ L[0-9.]+,[0-9.]+ L[0-9.]+,[0-9.]+ Z/g;
    while ((m = rb.exec(s))) B.push([+m[1], +m[2], +m[3], +m[4]]);
    var rk = /<g id="gnuplot_plot_[^"]*" ><title>[^<]*<\/title>\s*<g [^>]*>\s*<g transform="translate\(([0-9.]+),([0-9.]+)\)[^>]*>\s*<text>([\s\S]*?)<\/text>/g;
    while ((m = rk.exec(s))) {
      keys++;
      var x = +m[1], y = +m[2];
      for (var b = 0; b < B.length; b++)
        if (x > Math.min(B[b][0], B[b][3]) && x < Math.max(B[b][0], B[b][3]) &&
            y > Math.min(B[b][1], B[b][2]) && y < Math.max(B[b][1], B[b][2])) {
          bad.push(i + ': ' + m[3].replace(/<[^>]*>/g, ''));
          break;
        }
    }
  }
  var d = document.createElement('div'); d.id = 'figure-check';
  d.setAttribute('data-total', imgs.length); d.setAttribute('data-shown', ok);
  d.setAttribute('data-ink', ink.join(' ')); d.setAttribute('data-keys', keys);
  d.setAttribute('data-overlaps', bad.join('|'));
  document.body.appendChild(d);
});</script></body>)JS";
  const auto k = page.rfind("</body>");
  EXPECT_NE(k, std::string::npos);
  page.replace(k, 7, probe);
  const std::filesystem::path probed = dir / "probed.html";
  std::ofstream(probed) << page;
  const std::filesystem::path profile = dir / "chromium-profile";
  std::filesystem::create_directories(profile);
  const std::string cmd =
      "/usr/bin/chromium --headless --no-sandbox --disable-gpu --disable-background-networking "
      "--no-first-run --user-data-dir=" +
      quote(profile.string()) + " --virtual-time-budget=20000 --dump-dom " +
      quote("file://" + probed.string()) + " 2>/dev/null";
  std::string dom;
  if (FILE* pipe = ::popen(cmd.c_str(), "r")) {
    char buf[65536];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) dom.append(buf, n);
    ::pclose(pipe);
  }
  RenderedFigures f;
  std::smatch m;
  if (!std::regex_search(dom, m,
                         std::regex("id=\"figure-check\" data-total=\"([0-9]+)\" data-shown=\"("
                                    "[0-9]+)\" data-ink=\"([0-9. ]*)\" data-keys=\"([0-9]+)\" "
                                    "data-overlaps=\"([^\"]*)\"")))
    return f;
  f.total = std::stoi(m[1]);
  f.shown = std::stoi(m[2]);
  std::istringstream ink(m[3].str());
  for (double share; ink >> share;) f.ink.push_back(share);
  f.legend_entries = std::stoi(m[4]);
  std::istringstream bad(m[5].str());
  for (std::string entry; std::getline(bad, entry, '|');)
    if (!entry.empty()) f.overlapping.push_back(entry);
  return f;
}

/// A screenshot of the page's top, kept under the build folder (a CI artefact):
/// RICOCHET_BINARY_DIR/report-screenshots/NAME. Returns its path (absent if Chromium failed).
inline std::filesystem::path screenshot(const std::filesystem::path& html,
                                        const std::filesystem::path& dir, const std::string& name) {
  const std::filesystem::path shots =
      std::filesystem::path(RICOCHET_BINARY_DIR) / "report-screenshots";
  std::filesystem::create_directories(shots);
  const std::filesystem::path png = shots / name;
  std::filesystem::remove(png);
  const std::string cmd =
      "/usr/bin/chromium --headless --no-sandbox --disable-gpu --no-first-run --user-data-dir=" +
      quote((dir / "chromium-shot").string()) +
      " --window-size=1300,2400 --screenshot=" + quote(png.string()) + " " +
      quote("file://" + html.string()) + " >/dev/null 2>&1";
  std::system(cmd.c_str());
  return png;
}

}  // namespace ricochet::test
