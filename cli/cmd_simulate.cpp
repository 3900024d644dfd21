// `ricochet simulate`: one collision of the reduced engine (docs/commands/simulate.md).
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "engine/engine.hpp"
#include "model_options.hpp"
#include "shared_options.hpp"

namespace ricochet::cli {
namespace {

struct SimulateOptions {
  ModelOptions model;
  OutputOptions output;
  std::string vin;
  double alpha_deg = 0.0;
  bool trace = false;
};

void write_trace_csv(const Trace& tr, const std::string& path) {
  CsvTable t;
  t.row({"t[s]", "x[m]", "y[m]", "theta[rad]", "vx[m/s]", "vy[m/s]", "w[rad/s]", "fn[N]", "ft[N]",
         "moment[N m]", "h[m]"});
  for (std::size_t i = 0; i < tr.t.size(); ++i)
    t.row({CsvTable::num(tr.t[i]), CsvTable::num(tr.x[i]), CsvTable::num(tr.y[i]),
           CsvTable::num(tr.theta[i]), CsvTable::num(tr.vx[i]), CsvTable::num(tr.vy[i]),
           CsvTable::num(tr.w[i]), CsvTable::num(tr.fn[i]), CsvTable::num(tr.ft[i]),
           CsvTable::num(tr.moment[i]), CsvTable::num(tr.h[i])});
  t.write(path);
}

void run(const SimulateOptions& o) {
  const CollisionCase c{parse_vin(o.vin), o.alpha_deg * M_PI / 180.0};
  const Model model = o.model.build_model();
  const Shape shape = o.model.build_shape();
  const EngineOptions engine = o.model.engine_options();
  Trace trace;
  const bool want_trace = !o.output.out.empty();
  const CollisionResult r = simulate(model, shape, c, {}, engine, want_trace ? &trace : nullptr);

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
  j["dt"] = engine.dt_s;

  if (want_trace) {
    const auto& out = o.output.out;
    require_extension("--out", out, {".csv", ".h5", ".hdf5"});
    if (out.ends_with(".csv")) {
      write_trace_csv(trace, out);
    } else {
      h5::File f(out, h5::File::Mode::kTruncate);
      const std::vector<std::pair<const char*, const std::vector<double>*>> cols = {
          {"t", &trace.t},   {"x", &trace.x},           {"y", &trace.y}, {"theta", &trace.theta},
          {"vx", &trace.vx}, {"vy", &trace.vy},         {"w", &trace.w}, {"fn", &trace.fn},
          {"ft", &trace.ft}, {"moment", &trace.moment}, {"h", &trace.h}};
      for (const auto& [name, v] : cols) f.write(std::string("/trace/") + name, *v);
      f.set_attr("/", "summary", j.dump());
      f.set_attr("/", "model_toml", model.to_toml());
    }
  }
  if (o.output.json) {
    print_json(j);
    return;
  }
  std::printf("%s collision, V_in = (%.3f m/s, %.3f m/s, %.2f rad/s), alpha_in = %.1f deg\n",
              shape.name.c_str(), c.vin[0], c.vin[1], c.vin[2], o.alpha_deg);
  std::printf("  V_out            = (%.3f m/s, %.3f m/s, %.2f rad/s)  [%s]\n", r.vout[0], r.vout[1],
              r.vout[2], status_name(r.status));
  std::printf("  contact duration = %.2f ms in %d phase(s), max penetration = %.2f mm\n",
              r.contact_duration_s * 1e3, r.contact_phases, r.max_penetration_m * 1e3);
  std::printf(
      "  dissipated       = normal %.2f J, tangential %.2f J, rolling %.2f J, body %.2f J\n",
      r.dissipated_J[1], r.dissipated_J[2], r.dissipated_J[3], r.dissipated_J[4]);
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto opts = std::make_shared<SimulateOptions>();
  CLI::App* sub = app.add_subcommand("simulate", "Run one collision of the reduced engine");
  add_vin_option(sub, opts->vin, "Incident state")->required();
  sub->add_option("--alpha", opts->alpha_deg, "Incidence angle alpha_in [deg]");
  add_model_options(sub, opts->model);
  add_output_options(sub, opts->output);
  check_range(sub, "--alpha", -360, 360);
  sub->callback([opts] { run(*opts); });
}

}  // namespace ricochet::cli
