#include "report/impact_picture.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace ricochet::report {
namespace {

// Millimetres on the axes: short tick labels under narrow panels.
constexpr double kMm = 1e3;
std::vector<double> mm(const std::vector<double>& m) {
  std::vector<double> out(m.size());
  std::transform(m.begin(), m.end(), out.begin(), [](double v) { return kMm * v; });
  return out;
}

}  // namespace

Figure impact_picture(const ImpactSnapshot& snap, const std::string& title) {
  if (snap.frames.empty())
    throw std::invalid_argument("impact picture: the snapshot of " + snap.impact_id +
                                " has no frame");
  double vmax = 0, xlo = 1e300, xhi = -1e300, zlo = 1e300, zhi = -1e300;
  for (const auto& f : snap.frames) {
    for (double v : f.grain_speed_mps) vmax = std::max(vmax, v);
    for (std::size_t i = 0; i < f.grain_x_m.size(); ++i) {
      xlo = std::min(xlo, f.grain_x_m[i] - f.grain_radius_m[i]);
      xhi = std::max(xhi, f.grain_x_m[i] + f.grain_radius_m[i]);
      zlo = std::min(zlo, f.grain_z_m[i] - f.grain_radius_m[i]);
    }
    for (std::size_t i = 0; i < f.block_x_m.size(); ++i)
      zhi = std::max(zhi, f.block_z_m[i] + f.block_radius_m[i]);
  }
  Figure fig;
  fig.title = fmt::format("{}: impact {}, section {:.1f} mm thick through the block's mid-plane",
                          title, snap.impact_id, 2e3 * snap.section_half_width_m);
  fig.columns = static_cast<int>(snap.frames.size());
  fig.width_px = 320 * fig.columns + 100;
  // Equal scales on x and z: the height follows the section's aspect (about 80 px of titles
  // and labels around a plot about 240 px wide).
  const double aspect = (zhi + 0.01 - zlo) / std::max(xhi - xlo, 1e-9);
  fig.height_px = 150 + static_cast<int>(240 * std::clamp(aspect, 0.2, 2.0));
  for (std::size_t k = 0; k < snap.frames.size(); ++k) {
    const auto& f = snap.frames[k];
    Panel p;
    p.title = fmt::format("t = {:.1f} ms{}", 1e3 * f.t_s, f.max_penetration ? " (deepest)" : "");
    p.xlabel = "x [mm]";
    p.ylabel = k == 0 ? "z [mm]" : "";
    p.key = "off";
    p.equal_aspect = true;
    p.xmin = kMm * xlo, p.xmax = kMm * xhi, p.ymin = kMm * zlo, p.ymax = kMm * (zhi + 0.01);
    p.cbmin = 0, p.cbmax = vmax > 0 ? vmax : 1;
    p.cblabel = "grain speed [m/s]";
    p.colorbox = k + 1 == snap.frames.size();
    Series g;
    g.title = "grains";
    g.style = "circles";
    g.x = mm(f.grain_x_m), g.y = mm(f.grain_z_m), g.radius = mm(f.grain_radius_m);
    g.value = f.grain_speed_mps;
    Series b;
    b.title = "block";
    b.style = "circles";
    b.color = colour::kLightGrey;
    b.x = mm(f.block_x_m), b.y = mm(f.block_z_m), b.radius = mm(f.block_radius_m);
    p.series = {b, g};
    fig.panels.push_back(std::move(p));
  }
  return fig;
}

}  // namespace ricochet::report
