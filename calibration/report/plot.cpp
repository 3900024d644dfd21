// Gnuplot SVG rendering (see plot.hpp). Design choices:
//  - Every series goes to its own data file in a private temporary directory (mkdtemp), so no
//    data ever passes through a command line or the script text.
//  - gnuplot is started with posix_spawnp (no shell): paths and titles cannot be interpreted by
//    a shell. Text reaches gnuplot only inside single-quoted strings, where the sole special
//    character is the quote itself (doubled), and control characters are replaced by spaces.
//  - gnuplot writes into the temporary directory; the SVG is copied to its destination only
//    when gnuplot succeeded, so a failed render never leaves a truncated figure behind.
#include "report/plot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "stats/stats.hpp"

extern char** environ;

namespace ricochet::report {
namespace {

namespace fs = std::filesystem;

/// A private temporary directory removed with its content on scope exit.
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "ricochet-plot-XXXXXX").string();
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    if (mkdtemp(buf.data()) == nullptr)
      throw std::runtime_error("plot: cannot create a temporary directory from '" + tmpl +
                               "': " + std::strerror(errno));
    path_ = buf.data();
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// gnuplot single-quoted string: only the quote is special (written twice). Control characters
/// (newlines would end the command) become spaces.
std::string quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'')
      out += "''";
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      out += ' ';
    else
      out += c;
  }
  out += "'";
  return out;
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

bool is_known_style(const std::string& style) {
  static const char* const kStyles[] = {"lines",     "points",       "linespoints", "steps",
                                        "errorbars", "filledcurves", "circles"};
  return std::any_of(std::begin(kStyles), std::end(kStyles),
                     [&](const char* s) { return style == s; });
}

void check_series(const Panel& panel, std::size_t p, const Series& s, std::size_t k) {
  const std::string where = "plot: panel " + std::to_string(p + 1) + " ('" + panel.title +
                            "'), series " + std::to_string(k + 1) + " ('" + s.title + "'): ";
  if (!is_known_style(s.style))
    throw std::invalid_argument(where + "unknown style '" + s.style +
                                "' (known: lines, points, linespoints, steps, errorbars, "
                                "filledcurves, circles)");
  const bool band = s.style == "errorbars" || s.style == "filledcurves";
  if (s.style != "filledcurves" && s.x.size() != s.y.size())
    throw std::invalid_argument(where + "x and y have different lengths (" +
                                std::to_string(s.x.size()) + " and " + std::to_string(s.y.size()) +
                                ")");
  if (band && (s.ylo.size() != s.x.size() || s.yhi.size() != s.x.size()))
    throw std::invalid_argument(where + "style '" + s.style +
                                "' needs ylo and yhi of the length of x");
  if (s.style == "circles" &&
      (s.radius.size() != s.x.size() || (s.color.empty() && s.value.size() != s.x.size())))
    throw std::invalid_argument(where +
                                "style 'circles' needs radius (and value, unless a colour is "
                                "set) of the length of x");
  for (char c : s.color)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '#' || c == '-' || c == '_'))
      throw std::invalid_argument(where + "colour '" + s.color +
                                  "' is neither a gnuplot colour name nor #rrggbb");
}

/// A point is drawable when every coordinate is finite and positive on a log axis.
bool drawable(double v, bool log_axis) {
  return std::isfinite(v) && (!log_axis || v > 0);
}

/// Writes the series' points; an undrawable point (NaN, inf, non-positive on a log axis) becomes
/// a blank line, which gnuplot treats as a break: lines are not drawn across missing data.
/// Returns the number of drawable points.
std::size_t write_series(const Series& s, const Panel& panel, const fs::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("plot: cannot write temporary data file " + file.string());
  std::size_t drawn = 0;
  bool last_blank = true;
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    std::vector<double> row{s.x[i]};
    if (s.style != "filledcurves") row.push_back(s.y[i]);
    if (s.style == "errorbars" || s.style == "filledcurves") {
      row.push_back(s.ylo[i]);
      row.push_back(s.yhi[i]);
    }
    if (s.style == "circles") {
      row.push_back(s.radius[i]);
      if (s.color.empty()) row.push_back(s.value[i]);
    }
    bool ok = drawable(row[0], panel.logx);
    for (std::size_t c = 1; c < row.size(); ++c) ok = ok && drawable(row[c], panel.logy);
    if (!ok) {
      if (!last_blank) out << "\n";
      last_blank = true;
      continue;
    }
    for (std::size_t c = 0; c < row.size(); ++c) out << (c ? " " : "") << number(row[c]);
    out << "\n";
    last_blank = false;
    ++drawn;
  }
  if (!out) throw std::runtime_error("plot: cannot write temporary data file " + file.string());
  return drawn;
}

std::string style_clause(const Series& s) {
  std::string clause;
  if (s.style == "points")
    clause = "with points pt " + std::to_string(s.point_type);
  else if (s.style == "linespoints")
    clause = "with linespoints pt " + std::to_string(s.point_type);
  else if (s.style == "errorbars")
    clause = "with yerrorbars pt " + std::to_string(s.point_type);
  else if (s.style == "filledcurves")
    clause = "with filledcurves fs transparent solid 0.3 noborder";
  else if (s.style == "circles")
    return "with circles fs solid 1.0 noborder lc " +
           (s.color.empty() ? std::string("palette") : "rgb " + quote(s.color));
  else
    clause = "with " + s.style;
  if (!s.color.empty()) clause += " lc rgb " + quote(s.color);
  return clause;
}

std::string using_clause(const Series& s) {
  if (s.style == "errorbars") return "using 1:2:3:4";
  if (s.style == "filledcurves") return "using 1:2:3";
  if (s.style == "circles") return s.color.empty() ? "using 1:2:3:4" : "using 1:2:3";
  return "using 1:2";
}

void range(std::ostream& script, const char* axis, double lo, double hi) {
  script << "set " << axis << "range [" << (std::isnan(lo) ? "*" : number(lo)) << ":"
         << (std::isnan(hi) ? "*" : number(hi)) << "]\n";
}

// No legend covers data: every legend is outside the plot area (under it by default), or off.
std::string key_clause(const std::string& key) {
  if (key.empty()) return "set key default\nset key outside bottom center horizontal\n";
  std::istringstream words(key);
  std::string w;
  bool outside = false;
  static const char* const kAllowed[] = {"left",   "right",      "center",  "top",
                                         "bottom", "outside",    "off",     "box",
                                         "nobox",  "horizontal", "vertical"};
  while (words >> w) {
    if (std::none_of(std::begin(kAllowed), std::end(kAllowed),
                     [&](const char* a) { return w == a; }))
      throw std::invalid_argument("plot: unknown key position word '" + w +
                                  "' (use outside with left, right, center, top, bottom, "
                                  "horizontal, vertical, box; or off)");
    outside = outside || w == "outside";
  }
  if (key == "off") return "unset key\n";
  if (!outside)
    throw std::invalid_argument("plot: legend '" + key +
                                "' would sit inside the plot, over the data: use 'outside ...', "
                                "'off', or the default (empty: under the plot)");
  return "set key default\nset key " + key + "\n";
}

bool uses_colour_map(const Figure& f) {
  for (const auto& p : f.panels)
    for (const auto& s : p.series)
      if (s.style == "circles" && s.color.empty()) return true;
  return false;
}

/// The gnuplot program: RICOCHET_GNUPLOT when set (tests use it to simulate a missing or failing
/// gnuplot), else `gnuplot` from PATH.
std::string gnuplot_program() {
  const char* env = std::getenv("RICOCHET_GNUPLOT");
  return env && *env ? env : "gnuplot";
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Runs gnuplot on `script` with stdout/stderr captured into `log`; throws with its message.
void run_gnuplot(const fs::path& script, const fs::path& log, const fs::path& cwd) {
  const std::string program = gnuplot_program();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  // The script refers to its data files by name relative to the temporary directory.
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 29))
  posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
#else
#error "plot.cpp needs posix_spawn_file_actions_addchdir_np (glibc >= 2.29)"
#endif
  std::string script_arg = script.filename().string();
  std::vector<char*> argv{const_cast<char*>(program.c_str()), script_arg.data(), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0)
    throw std::runtime_error("plot: cannot run '" + program + "' (" + std::strerror(rc) +
                             "); install gnuplot (Debian package gnuplot-nox)");
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error("plot: waiting for gnuplot failed");
  }
  std::string message = read_file(log);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
    throw std::runtime_error("plot: '" + program +
                             "' could not be executed; install gnuplot (Debian package "
                             "gnuplot-nox)" +
                             (message.empty() ? "" : ": " + message));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("plot: gnuplot failed (" +
                             (WIFEXITED(status)
                                  ? "exit status " + std::to_string(WEXITSTATUS(status))
                                  : std::string("killed by a signal")) +
                             ")" + (message.empty() ? "" : ":\n" + message));
}

}  // namespace

namespace {

void check_figure(const Figure& figure, const std::string& path, const std::string& ext) {
  if (ext != ".svg" && ext != ".png")
    throw std::invalid_argument("plot: cannot write '" + path +
                                "': the figure formats are .svg and .png");
  if (figure.panels.empty())
    throw std::invalid_argument("plot: figure '" + figure.title + "' has no panel");
  if (figure.columns < 1 || figure.width_px < 1 || figure.height_px < 1)
    throw std::invalid_argument("plot: figure columns, width and height must be positive");
  for (std::size_t p = 0; p < figure.panels.size(); ++p)
    for (std::size_t k = 0; k < figure.panels[p].series.size(); ++k)
      check_series(figure.panels[p], p, figure.panels[p].series[k], k);
}

// The step of a linear axis's ticks so that at most `max_ticks` intervals span [lo, hi]: the
// smallest of 1, 2, 2.5, 5 x 10^k that does. gnuplot's own choice ignores the panel's width, and
// on the narrow panels of a wide grid (six parameters side by side) its labels ran together.
double tick_step(double lo, double hi, int max_ticks) {
  const double span = hi - lo;
  if (!(span > 0) || !std::isfinite(span) || max_ticks < 1) return 0;
  const double raw = span / max_ticks;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 2.5, 5.0})
    if (m * decade >= raw * (1 - 1e-9)) return m * decade;
  return 10 * decade;
}

// The x range that the panel shows: its fixed bounds, else its drawable points' extent.
std::pair<double, double> x_extent(const Panel& panel) {
  double lo = panel.xmin, hi = panel.xmax;
  if (!std::isnan(lo) && !std::isnan(hi)) return {lo, hi};
  double dlo = std::numeric_limits<double>::infinity(), dhi = -dlo;
  for (const Series& s : panel.series)
    for (double x : s.x)
      if (drawable(x, panel.logx)) {
        dlo = std::min(dlo, x);
        dhi = std::max(dhi, x);
      }
  return {std::isnan(lo) ? dlo : lo, std::isnan(hi) ? dhi : hi};
}

// The terminal, the output file, the project's style and the multiplot layout.
void figure_preamble(std::ostringstream& script, const Figure& figure, const std::string& ext,
                     const std::string& produced_name) {
  const std::size_t columns =
      std::min<std::size_t>(static_cast<std::size_t>(figure.columns), figure.panels.size());
  const std::size_t rows = (figure.panels.size() + columns - 1) / columns;
  if (ext == ".svg")
    script << "set terminal svg size " << figure.width_px << "," << figure.height_px << " dynamic "
           << (figure.enhanced_text ? "enhanced" : "noenhanced")
           << " font 'sans,11' background rgb 'white'\n";
  else  // libgd's png: an indexed palette, a third of pngcairo's bytes for plots (report size);
        // true colour when the colour map needs more than its 256 entries.
    script << "set terminal png " << (uses_colour_map(figure) ? "truecolor " : "") << "size "
           << figure.width_px << "," << figure.height_px << " "
           << (figure.enhanced_text ? "enhanced" : "noenhanced")
           << " font 'sans,10' background rgb 'white'\n";
  script << "set output " << quote(produced_name) << "\n";
  // The project's one style: the Okabe-Ito colour sequence for automatic colours (it holds
  // across every panel: `reset` leaves line types alone).
  script << "set colorsequence podo\n";
  script << "set datafile missing 'NaN'\n";
  script << "set multiplot layout " << rows << "," << columns;
  if (!figure.title.empty()) script << " title " << quote(figure.title);
  script << "\n";
}

// Panel p: its settings, its series written as data files in `dir`, and its plot command.
void panel_script(std::ostringstream& script, const Panel& panel, std::size_t p,
                  const fs::path& dir, double panel_width_px) {
  script << "reset\n";
  script << "set title " << quote(panel.title) << "\n";
  script << "set xlabel " << quote(panel.xlabel) << "\n";
  script << "set ylabel " << quote(panel.ylabel) << "\n";
  script << "set grid\n";
  script << key_clause(panel.key);
  script << (panel.logx ? "set logscale x\n" : "unset logscale x\n");
  script << (panel.logy ? "set logscale y\n" : "unset logscale y\n");
  std::vector<std::string> items;
  std::size_t drawn_total = 0;
  for (std::size_t k = 0; k < panel.series.size(); ++k) {
    const Series& s = panel.series[k];
    const std::string file = "p" + std::to_string(p) + "_s" + std::to_string(k) + ".dat";
    const std::size_t drawn = write_series(s, panel, dir / file);
    drawn_total += drawn;
    // A series without drawable points keeps its legend entry (keyentry) so that the reader
    // sees it is empty rather than silently missing.
    if (drawn == 0)
      items.push_back("keyentry " + style_clause(s) + " title " + quote(s.title + " (no data)"));
    else
      items.push_back(quote(file) + " " + using_clause(s) + " " + style_clause(s) + " title " +
                      quote(s.title));
  }
  // gnuplot refuses to autoscale an axis without any point: give empty panels a unit box.
  double xmin = panel.xmin, xmax = panel.xmax, ymin = panel.ymin, ymax = panel.ymax;
  if (drawn_total == 0) {
    const double lo = 1, hi = 10;
    if (std::isnan(xmin)) xmin = panel.logx ? lo : 0;
    if (std::isnan(xmax)) xmax = panel.logx ? hi : 1;
    if (std::isnan(ymin)) ymin = panel.logy ? lo : 0;
    if (std::isnan(ymax)) ymax = panel.logy ? hi : 1;
  }
  range(script, "x", xmin, xmax);
  range(script, "y", ymin, ymax);
  // About 70 px per x tick label (a label such as "0.55" is about 30 px at the 11 pt font).
  if (!panel.logx && drawn_total > 0) {
    const auto [lo, hi] = x_extent(panel);
    const double step = tick_step(lo, hi, std::max(2, static_cast<int>(panel_width_px / 70)));
    if (step > 0) script << "set xtics " << number(step) << "\n";
  }
  if (panel.equal_aspect) script << "set size ratio -1\n";
  // viridis (van der Walt and Smith 2015), sampled at 5 stops: colour-blind-safe and
  // readable in grey.
  script << "set palette defined (0 '#440154', 1 '#3b528b', 2 '#21918c', 3 '#5ec962', "
            "4 '#fde725')\n";
  range(script, "cb", panel.cbmin, panel.cbmax);
  if (!panel.cblabel.empty()) script << "set cblabel " << quote(panel.cblabel) << "\n";
  if (!panel.colorbox) script << "unset colorbox\n";
  // gnuplot cannot draw axes from legend entries alone (it asserts): a panel without any
  // drawable point gets an invisible placeholder curve, so it still renders its frame, its
  // title and the "(no data)" entries in its place of the grid.
  if (drawn_total == 0) items.insert(items.begin(), "-1 notitle with lines lt nodraw");
  script << "plot ";
  for (std::size_t i = 0; i < items.size(); ++i) script << (i ? ", \\\n     " : "") << items[i];
  script << "\n";
}

// Runs the script in `dir` and copies gnuplot's output to `path`.
void run_script(const std::string& script, const fs::path& dir, const std::string& ext,
                const std::string& produced_name, const std::string& path) {
  const fs::path script_path = dir / "figure.gp";
  {
    std::ofstream out(script_path);
    out << script;
    if (!out) throw std::runtime_error("plot: cannot write " + script_path.string());
  }
  run_gnuplot(script_path, dir / "gnuplot.log", dir);
  const fs::path produced = dir / produced_name;
  std::error_code ec;
  if (!fs::exists(produced) || fs::file_size(produced, ec) == 0)
    throw std::runtime_error("plot: gnuplot produced no " + ext.substr(1) + " output:\n" +
                             read_file(dir / "gnuplot.log"));
  const fs::path dest(path);
  if (dest.has_parent_path()) fs::create_directories(dest.parent_path());
  fs::copy_file(produced, dest, fs::copy_options::overwrite_existing, ec);
  if (ec) throw std::runtime_error("plot: cannot write " + path + ": " + ec.message());
}

}  // namespace

void render(const Figure& figure, const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  check_figure(figure, path, ext);
  TempDir dir;
  const std::string produced_name = "figure" + ext;
  std::ostringstream script;
  figure_preamble(script, figure, ext, produced_name);
  const double panel_width_px =
      static_cast<double>(figure.width_px) /
      static_cast<double>(std::min<std::size_t>(std::max(1, figure.columns), figure.panels.size()));
  for (std::size_t p = 0; p < figure.panels.size(); ++p)
    panel_script(script, figure.panels[p], p, dir.path(), panel_width_px);
  script << "unset multiplot\nset output\n";
  run_script(script.str(), dir.path(), ext, produced_name, path);
}

Panel ecdf_panel(const std::string& title, const std::string& xlabel,
                 const std::vector<std::pair<std::string, std::vector<double>>>& samples) {
  Panel panel;
  panel.title = title;
  panel.xlabel = xlabel;
  panel.ylabel = "cumulative probability";
  panel.ymin = 0;
  panel.ymax = 1;
  panel.key = "";
  for (const auto& [name, values] : samples) {
    std::vector<double> finite;
    std::copy_if(values.begin(), values.end(), std::back_inserter(finite),
                 [](double v) { return std::isfinite(v); });
    const stats::Ecdf e = stats::ecdf(finite);
    Series s;
    s.title = name;
    s.style = "steps";
    // Start the staircase at probability 0 at the smallest value, so the first step is drawn
    // (right-continuous ECDF: F(x) = #{x_i <= x} / n).
    if (!e.x.empty()) {
      s.x.push_back(e.x.front());
      s.y.push_back(0.0);
    }
    s.x.insert(s.x.end(), e.x.begin(), e.x.end());
    s.y.insert(s.y.end(), e.p.begin(), e.p.end());
    panel.series.push_back(std::move(s));
  }
  return panel;
}

}  // namespace ricochet::report
