// The impact-set schema: the one data format every Ricochet tool reads and writes.
//
// A set of impacts (releases) is the same thing whatever its source: lab measurements (paper
// Appendix A), a LIGGGHTS campaign, or synthetic data from a truth model. Statistics, the
// transfer matrix, calibration, Monte Carlo comparison, Sobol, diagnosis and the report all take
// an ImpactSet; there is no second path for the same data.
//
// Frame (paper Fig. 1 and 8): 2-D flight plane, x horizontal in the direction of travel, y up,
// rotation omega > 0 counter-clockwise. A block rolling forward in +x has omega < 0.
//
// File forms (both carry the same columns and units):
//  - CSV: optional '#' comment lines, then a header row of `name[unit]` cells (text columns
//    `id`, `shape`, `operator` have no unit), then one row per release. See docs/impact-sets.md.
//  - HDF5: group /impacts with one 1-D dataset per column, attribute "unit" on each numeric
//    dataset; attribute "schema" = "ricochet-impact-set-1" on the group.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ricochet {

/// Velocity state of a 2-D rigid block: {vx [m/s], vy [m/s], omega [rad/s]}.
using Vel3 = std::array<double, 3>;
enum Component : int { kVx = 0, kVy = 1, kW = 2 };
/// Short names of the three components as used in JSON keys and column names.
inline constexpr std::array<const char*, 3> kComponentNames = {"vx", "vy", "w"};

/// One release: incident and reflected velocities plus optional measured features.
/// All numeric fields are SI (m, s, rad); the readers convert from the file's units.
struct Impact {
  std::string id;     ///< unique within the set (lab: table order, e.g. "C01")
  std::string shape;  ///< "cylinder", "triangle", or the name of a shape file
  Vel3 vin{};         ///< incident velocity (m/s, m/s, rad/s), vin[kVy] < 0
  Vel3 vout{};        ///< reflected velocity (m/s, m/s, rad/s), vout[kVy] > 0

  std::optional<double> alpha_in;          ///< incidence angle of the block [rad]
  std::optional<double> penetration;       ///< maximum penetration depth [m]
  std::optional<double> contact_duration;  ///< contact duration [s]
  std::optional<std::string> op;           ///< operator who processed the record
  /// Replicate label: releases sharing it repeat the same experiment (same nominal incident
  /// state, block and ground parameters; e.g. a resolved campaign's replica beds or positions).
  /// The diagnosis's noise floor pools their scatter (docs/diagnosis.md, "Noise floor").
  std::optional<std::string> replicate;
  std::optional<double> weight;  ///< statistical weight [-], default 1
  /// Measurement standard uncertainty of vin / vout (same units as vin / vout), when known
  /// (reconstruction standard errors, LIGGGHTS extraction errors, synthetic noise level).
  std::optional<Vel3> sigma_vin;
  std::optional<Vel3> sigma_vout;
  /// Extra numeric features (e.g. crater width, dissipated energy), aligned with
  /// ImpactSet::extra_names, SI units as declared in ImpactSet::extra_units. NaN = missing.
  std::vector<double> extra;
};

/// A named collection of impacts with provenance.
struct ImpactSet {
  std::string source;                    ///< file the set was read from, or a description
  std::vector<std::string> comments;     ///< free-text provenance lines ('#' lines in CSV)
  std::vector<std::string> extra_names;  ///< names of extra numeric columns
  std::vector<std::string> extra_units;  ///< their SI units after conversion
  std::vector<Impact> impacts;

  std::size_t size() const { return impacts.size(); }
  bool empty() const { return impacts.empty(); }

  /// Values of one named feature over all impacts, NaN where missing. Known names: vin_x,
  /// vin_y, win, vout_x, vout_y, wout, speed_in (|V_in|), alpha_in, penetration,
  /// contact_duration, weight, and every extra column. Throws std::invalid_argument listing
  /// the known names for an unknown one.
  std::vector<double> feature(const std::string& name) const;
  /// All feature names available in this set (those with at least one value).
  std::vector<std::string> feature_names() const;
  /// Impacts whose shape equals `shape` (all if empty).
  ImpactSet with_shape(const std::string& shape) const;
};

/// Groups of replicate releases (indices into set.impacts, groups of two or more only): releases
/// sharing a `replicate` label, and releases without one whose incident state and alpha_in are
/// identical. Used for noise estimates (diagnosis noise floor, upscaling intervals).
std::vector<std::vector<std::size_t>> replicate_groups(const ImpactSet& set);

/// Pooled within-group variance of the values x[i] over `groups`: the sum over groups of
/// sum (x - group mean)^2, over its degrees of freedom (members - number of groups). NaN when
/// there is none.
double pooled_variance(std::span<const double> x,
                       const std::vector<std::vector<std::size_t>>& groups);

/// Pooled within-group standard deviation of V_out over `groups` (m/s, m/s, rad/s):
/// sqrt(pooled_variance) per component.
Vel3 pooled_vout_sd(const ImpactSet& set, const std::vector<std::vector<std::size_t>>& groups);

/// Read an impact set; the format follows the extension (.csv, .h5/.hdf5). In CSV, an empty cell
/// of an optional column means absent; in HDF5, NaN or "" does.
/// Throws InputError naming file, line and column for malformed input: missing required column,
/// non-numeric cell, NaN or infinite value, vin_y >= 0 or vout_y <= 0, duplicate id, unknown unit.
ImpactSet read_impact_set(const std::string& path);
ImpactSet read_impact_set_csv(const std::string& path);
/// Parse CSV text directly (used by tests and the fuzz target); `name` is used in errors.
ImpactSet parse_impact_set_csv(const std::string& text, const std::string& name);
ImpactSet read_impact_set_h5(const std::string& path);

/// Read a set of incident states: a plan of throws (`ricochet design --out plan.csv`, docs/
/// commands/design.md) or any impact set. The impact-set reader with one difference: in CSV
/// the three reflected columns (vout_x, vout_y, wout) may be absent, all three together, and
/// each release's vout is then NaN (docs/impact-sets.md, "Incident states"); every other rule
/// holds (required incident columns, units, vin_y < 0, unique ids). A file with reflected
/// columns is read and checked as an impact set. HDF5 holds full impact sets only.
ImpactSet read_incident_states(const std::string& path);
ImpactSet read_incident_states_csv(const std::string& path);
ImpactSet parse_incident_states_csv(const std::string& text, const std::string& name);

/// Write an impact set; the format follows the extension (.csv, .h5/.hdf5).
/// Optional columns are written only when at least one impact has them.
void write_impact_set(const ImpactSet& set, const std::string& path);
void write_impact_set_csv(const ImpactSet& set, const std::string& path);
std::string format_impact_set_csv(const ImpactSet& set);
/// Writes (or replaces) the group `group` (default /impacts) in an HDF5 file, creating the
/// file if it does not exist. Other groups of an existing file are kept.
void write_impact_set_h5(const ImpactSet& set, const std::string& path,
                         const std::string& group = "impacts");

/// Re-check the schema's invariants on an in-memory set (as the readers do on files). Errors name
/// set.source, the impact's index + 1 as line, and the field. The writers call it first.
void validate(const ImpactSet& set);

/// A filter such as "vin_x<3.5", "vin_x>=3.5 && shape==triangle", "id!=C12".
/// Terms are `FEATURE OP VALUE` joined by "&&" (or "and"); OP in < <= > >= == !=; FEATURE is any
/// name accepted by ImpactSet::feature(), or `id`, `shape`, `operator`, `replicate` (text: ==, !=
/// and ^=, "starts with", only; e.g. "id^=E1.5e9-").
/// Numeric values are SI. A release without the feature matches no condition on it. An empty
/// filter keeps everything; the result's comments gain "filter: WHERE".
/// Throws InputError (file `option`, field = the offending term) for a malformed filter; `option`
/// is the command-line option the filter came from (--where, or calibrate-grains' --lab-where).
ImpactSet filter(const ImpactSet& set, const std::string& where,
                 const std::string& option = "--where");

/// filter(set, where) as the commands apply --where: a non-empty filter that keeps no release is an
/// InputError (field `option`) saying so, naming `where` and `source` (the file `set` came from),
/// rather than an empty set that fails later with a less telling message.
ImpactSet filter_nonempty(const ImpactSet& set, const std::string& where, const std::string& source,
                          const std::string& option = "--where");

}  // namespace ricochet
