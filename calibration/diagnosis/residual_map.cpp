#include "diagnosis/residual_map.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/json_number.hpp"
#include "stats/stats.hpp"

namespace ricochet::diagnosis {
namespace {

constexpr const char* kBranch[2] = {"loading", "unloading"};

std::size_t band_of(double h, double h_max) {
  const double f = h_max > 0.0 ? h / h_max : 0.0;
  return std::min<std::size_t>(ResidualMap::kBands - 1,
                               static_cast<std::size_t>(f * ResidualMap::kBands));
}

}  // namespace

ResidualMap residual_map(std::span<const ReleaseResidual> residuals) {
  // Per cell and component, each release's mean residual there (NaN where it has samples but
  // not that component: stats::summarize skips it).
  std::array<std::array<std::array<std::vector<double>, kForceComponents>, ResidualMap::kBands>, 2>
      release_means;
  ResidualMap map;
  for (const ReleaseResidual& r : residuals) {
    double h_max = 0.0;
    for (const ContactSample& s : r.samples) h_max = std::max(h_max, s.h_m);
    std::array<std::array<std::array<double, kForceComponents>, ResidualMap::kBands>, 2> acc{};
    std::array<std::array<std::array<std::size_t, kForceComponents>, ResidualMap::kBands>, 2>
        count{};
    std::array<std::array<std::size_t, ResidualMap::kBands>, 2> samples{};
    for (std::size_t i = 0; i < r.samples.size(); ++i) {
      const std::size_t b = r.samples[i].loading ? 0 : 1;
      const std::size_t d = band_of(r.samples[i].h_m, h_max);
      ++samples[b][d];
      for (std::size_t c = 0; c < kForceComponents; ++c)
        if (std::isfinite(r.residual[i][c])) {  // a component not measured is NaN
          acc[b][d][c] += r.residual[i][c];
          ++count[b][d][c];
        }
    }
    for (std::size_t b = 0; b < 2; ++b)
      for (std::size_t d = 0; d < ResidualMap::kBands; ++d) {
        if (samples[b][d] == 0) continue;
        ++map.cell[b][d].releases;
        map.cell[b][d].samples += samples[b][d];
        for (std::size_t c = 0; c < kForceComponents; ++c)
          release_means[b][d][c].push_back(count[b][d][c] > 0
                                               ? acc[b][d][c] / static_cast<double>(count[b][d][c])
                                               : std::numeric_limits<double>::quiet_NaN());
      }
  }
  for (std::size_t b = 0; b < 2; ++b)
    for (std::size_t d = 0; d < ResidualMap::kBands; ++d)
      for (std::size_t c = 0; c < kForceComponents; ++c) {
        // NaN mean without a release, NaN sd below two (summarize's rule).
        const stats::Summary s = stats::summarize(release_means[b][d][c]);
        map.cell[b][d].mean[c] = s.mean;
        map.cell[b][d].se[c] = s.std / std::sqrt(static_cast<double>(s.n));
      }
  return map;
}

nlohmann::json to_json(const ResidualMap& map) {
  nlohmann::json out = nlohmann::json::object();
  for (std::size_t b = 0; b < 2; ++b) {
    nlohmann::json bands = nlohmann::json::array();
    for (std::size_t d = 0; d < ResidualMap::kBands; ++d) {
      const ResidualCell& cell = map.cell[b][d];
      nlohmann::json mean = nlohmann::json::object(), se = nlohmann::json::object();
      for (std::size_t c = 0; c < kForceComponents; ++c) {
        const auto name = std::string(component_name(static_cast<ForceComponent>(c)));
        mean[name] = finite_or_null(cell.mean[c]);
        se[name] = finite_or_null(cell.se[c]);
      }
      bands.push_back({{"h_over_hmax",
                        {static_cast<double>(d) / ResidualMap::kBands,
                         static_cast<double>(d + 1) / ResidualMap::kBands}},
                       {"releases", cell.releases},
                       {"samples", cell.samples},
                       {"mean", mean},
                       {"se", se}});
    }
    out[kBranch[b]] = bands;
  }
  return out;
}

std::vector<std::string> residual_map_header() {
  return {"branch", "component", "h/h_max < 1/3", "1/3 - 2/3", "> 2/3"};
}

std::vector<std::vector<std::string>> residual_map_rows(const ResidualMap& map) {
  // A component measured in no cell (the torque of a set without it) has no rows; one measured
  // somewhere keeps both branches, an empty cell printed "-".
  std::array<bool, kForceComponents> measured{};
  for (const auto& branch : map.cell)
    for (const ResidualCell& cell : branch)
      for (std::size_t c = 0; c < kForceComponents; ++c)
        measured[c] = measured[c] || (cell.releases > 0 && std::isfinite(cell.mean[c]));
  std::vector<std::vector<std::string>> rows;
  for (std::size_t b = 0; b < 2; ++b)
    for (std::size_t c = 0; c < kForceComponents; ++c) {
      if (!measured[c]) continue;
      const auto comp = static_cast<ForceComponent>(c);
      std::vector<std::string> row = {kBranch[b],
                                      fmt::format("{} [{}]", component_name(comp),
                                                  comp == ForceComponent::kMoment ? "N m" : "N")};
      for (std::size_t d = 0; d < ResidualMap::kBands; ++d) {
        const ResidualCell& cell = map.cell[b][d];
        row.push_back(cell.releases == 0 || !std::isfinite(cell.mean[c]) ? "-"
                      : std::isfinite(cell.se[c])
                          ? fmt::format("{:.4g} +- {:.3g}", cell.mean[c], cell.se[c])
                          : fmt::format("{:.4g}", cell.mean[c]));
      }
      rows.push_back(std::move(row));
    }
  return rows;
}

std::string format_text(const ResidualMap& map) {
  std::string out = "  residual (measured - law) by branch and depth, mean +- se over releases:\n";
  const auto header = residual_map_header();
  out += fmt::format("    {:<10}{:<16}{:>22}{:>22}{:>22}\n", header[0], header[1], header[2],
                     header[3], header[4]);
  for (const auto& row : residual_map_rows(map))
    out +=
        fmt::format("    {:<10}{:<16}{:>22}{:>22}{:>22}\n", row[0], row[1], row[2], row[3], row[4]);
  return out;
}

}  // namespace ricochet::diagnosis
