#include "engine/engine_io.hpp"

#include <utility>
#include <vector>

#include "common/csv.hpp"
#include "common/h5.hpp"

namespace ricochet {

nlohmann::json collision_json(const CollisionResult& r, const Model& model, const Shape& shape,
                              const EngineOptions& options) {
  nlohmann::json j;
  j["vout"] = {r.vout[0], r.vout[1], r.vout[2]};
  j["contact_duration"] = r.contact_duration_s;
  j["max_penetration"] = r.max_penetration_m;
  j["contact_phases"] = r.contact_phases;
  j["status"] = status_name(r.status);
  j["alpha_out"] = r.alpha_out_rad;
  for (std::size_t s = 0; s < kStageCount; ++s)
    if (s != static_cast<std::size_t>(Stage::kCoefficient))
      j["dissipated"][std::string(stage_name(static_cast<Stage>(s)))] = r.dissipated_J[s];
  j["energy"] = {{"kinetic_in", r.kinetic_in_J},
                 {"kinetic_out", r.kinetic_out_J},
                 {"potential_change", r.potential_change_J}};
  j["model"] = model.to_json();
  j["shape"] = shape.name;
  j["dt"] = options.dt_s;
  return j;
}

void write_trace(const std::string& path, const Trace& tr, const nlohmann::json& summary,
                 const Model& model) {
  if (path.ends_with(".csv")) {
    CsvTable t;
    t.row({"t[s]", "x[m]", "y[m]", "theta[rad]", "vx[m/s]", "vy[m/s]", "w[rad/s]", "fn[N]", "ft[N]",
           "moment[N m]", "h[m]"});
    for (std::size_t i = 0; i < tr.t.size(); ++i)
      t.row({CsvTable::num(tr.t[i]), CsvTable::num(tr.x[i]), CsvTable::num(tr.y[i]),
             CsvTable::num(tr.theta[i]), CsvTable::num(tr.vx[i]), CsvTable::num(tr.vy[i]),
             CsvTable::num(tr.w[i]), CsvTable::num(tr.fn[i]), CsvTable::num(tr.ft[i]),
             CsvTable::num(tr.moment[i]), CsvTable::num(tr.h[i])});
    t.write(path);
    return;
  }
  h5::File f(path, h5::File::Mode::kTruncate);
  const std::vector<std::pair<const char*, const std::vector<double>*>> cols = {
      {"t", &tr.t},   {"x", &tr.x},           {"y", &tr.y}, {"theta", &tr.theta},
      {"vx", &tr.vx}, {"vy", &tr.vy},         {"w", &tr.w}, {"fn", &tr.fn},
      {"ft", &tr.ft}, {"moment", &tr.moment}, {"h", &tr.h}};
  for (const auto& [name, v] : cols) f.write(std::string("/trace/") + name, *v);
  f.set_attr("/", "summary", summary.dump());
  f.set_attr("/", "model_toml", model.to_toml());
}

}  // namespace ricochet
