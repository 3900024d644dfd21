// The engine's output layer: one collision (`ricochet simulate`) as JSON, and its time history as
// CSV or HDF5. Keys and columns: docs/commands/simulate.md.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"

namespace ricochet {

/// JSON of one collision: "vout" [m/s, m/s, rad/s], "contact_duration" [s], "max_penetration"
/// [m], "contact_phases", "status", "alpha_out" [rad], "dissipated" {stage: J}, "energy"
/// {kinetic_in, kinetic_out, potential_change} [J], "model", "shape", "dt" [s].
nlohmann::json collision_json(const CollisionResult& result, const Model& model, const Shape& shape,
                              const EngineOptions& options);

/// Writes a collision's time history by extension: .csv, one row per step with units in the
/// header (t[s], x[m], y[m], theta[rad], vx[m/s], vy[m/s], w[rad/s], fn[N], ft[N],
/// moment[N m], h[m]); .h5/.hdf5, one dataset per column under /trace with `summary` (the JSON
/// of collision_json) and the model's TOML as root attributes. The caller checks the extension.
void write_trace(const std::string& path, const Trace& trace, const nlohmann::json& summary,
                 const Model& model);

}  // namespace ricochet
