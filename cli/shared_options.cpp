#include "shared_options.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "engine/engine.hpp"
#include "fit/fit.hpp"

namespace ricochet::cli {

CLI::Option* add_vin_option(CLI::App* sub, std::string& text, const std::string& help) {
  // Bound to text, not to three doubles: a wrong count or a non-number then gets this program's
  // one message from parse_vin (CLI11 would word each failure its own way).
  return sub->add_option("--vin", text, help + " VX,VY,W [m/s, m/s, rad/s]");
}

Vel3 parse_vin(const std::string& text, bool falling) {
  const auto bad = [&](const std::string& what) {
    return InputError("<command line>", 0, "--vin", what + ", got '" + text + "'");
  };
  Vel3 v{};
  std::size_t k = 0, start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    std::string_view cell(text);
    cell = cell.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    while (!cell.empty() && cell.front() == ' ') cell.remove_prefix(1);
    while (!cell.empty() && cell.back() == ' ') cell.remove_suffix(1);
    if (cell.starts_with('+')) cell.remove_prefix(1);
    double x = 0;
    const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), x);
    if (k >= 3 || cell.empty() || ec != std::errc() || end != cell.data() + cell.size() ||
        !std::isfinite(x))
      throw bad("expected 3 numbers vx,vy,omega [m/s, m/s, rad/s]");
    v[k++] = x;
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (k != 3) throw bad("expected 3 numbers vx,vy,omega [m/s, m/s, rad/s]");
  if (falling && !(v[kVy] < 0)) throw bad("incident vy must be negative (downwards)");
  return v;
}

std::string format_vin(const Vel3& v) {
  return fmt::format("{:g},{:g},{:g}", v[0], v[1], v[2]);
}

CLI::Option* add_where_option(CLI::App* sub, std::string& where, const std::string& applies_to) {
  return sub->add_option("--where", where,
                         "Keep only " + applies_to +
                             " matching EXPR, e.g. \"vin_x<3.5\" or \"vin_x>=3.5 && "
                             "shape==triangle\" (SI units; docs/impact-sets.md)");
}

CLI::Option* add_figures_option(CLI::App* sub, std::string& dir, const std::string& what) {
  return sub->add_option("--figures", dir, "Write " + what + " into DIR");
}

CLI::Option* add_seed_option(CLI::App* sub, std::uint64_t& seed, const std::string& of) {
  return sub->add_option("--seed", seed, "Seed of " + of)->capture_default_str();
}

CLI::Option* add_seed_option(CLI::App* sub, std::optional<std::uint64_t>& seed,
                             const std::string& of) {
  return sub->add_option("--seed", seed, "Seed of " + of);
}

CLI::Option* add_threads_option(CLI::App* sub, int& threads) {
  CLI::Option* o =
      sub->add_option("--threads", threads, "OpenMP threads (0 = all)")->capture_default_str();
  check_range(sub, "--threads", EngineOptions::kThreads.lo, EngineOptions::kThreads.hi);
  return o;
}

void add_orientation_options(CLI::App* sub, int& search_points, int& polish_points) {
  sub->add_option("--orientations", search_points,
                  "Orientations of the search rule for blocks without alpha_in, in " +
                      fit::FitOptions::kMarginalPoints.text() + " (0: the default)")
      ->capture_default_str();
  sub->add_option("--polish-orientations", polish_points,
                  "Orientations of the refined rule (the fits' polish, every prediction) for "
                  "blocks without alpha_in, in " +
                      fit::FitOptions::kPolishPoints.text() + " (0: the search rule throughout)")
      ->capture_default_str();
}

}  // namespace ricochet::cli
