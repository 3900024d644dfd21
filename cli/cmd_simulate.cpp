// `ricochet simulate`: one collision of the reduced engine (docs/commands/simulate.md).
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "engine/engine.hpp"
#include "engine/engine_io.hpp"
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

void run(const SimulateOptions& o) {
  const CollisionCase c{parse_vin(o.vin), o.alpha_deg * M_PI / 180.0};
  const Model model = o.model.build_model();
  const Shape shape = o.model.build_shape();
  const EngineOptions engine = o.model.engine_options();
  Trace trace;
  const bool want_trace = !o.output.out.empty();
  const CollisionResult r = simulate(model, shape, c, {}, engine, want_trace ? &trace : nullptr);

  const nlohmann::json j = collision_json(r, model, shape, engine);

  if (want_trace) {
    const auto& out = o.output.out;
    require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
    write_trace(out, trace, j, model);
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
