// Synthetic impact sets from a truth model: the test bench of the diagnosis (issue 6).
//
// A truth model (any composition of effects with parameter values, e.g. the paper's law plus a
// hidden `rate_restitution`) is run by the reduced engine on incident states drawn like the lab's
// or over a wider design; measurement noise like the lab's is added; the result is an ordinary
// impact set (impact/impact_set.hpp) that any tool reads. The truth model is NOT written into
// the set: the diagnosing side must find the effect from the data alone. synthesize() returns it
// separately as provenance (`ricochet synth --truth FILE` writes it to a separate file).
//
// Randomness: OpenTURNS' generator through fit::uniform_unit_sample() (explicit seeds,
// serialised); normal deviates by the Box-Muller transform of those uniforms. The set depends
// only on the truth model, the shape and the options: bit for bit reproducible.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "common/option_problems.hpp"
#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::diagnosis {

/// Standard uncertainties (one standard deviation, Gaussian, independent) of synthetic
/// measurements, SI units.
struct NoiseSpec {
  Vel3 vin{};                     ///< of V_in (m/s, m/s, rad/s)
  Vel3 vout{};                    ///< of V_out (m/s, m/s, rad/s)
  double penetration_m = 0;       ///< of the maximum penetration [m]
  double contact_duration_s = 0;  ///< of the contact duration [s]

  /// The lab's scale (docs/diagnosis.md, "Noise"): fit::LabNoise (fit/lab_noise.hpp), the
  /// uncertainties the calibration and the noise floor use too.
  static NoiseSpec lab();
  /// No noise: exact measurements.
  static NoiseSpec none() { return {}; }
  /// Parses the --noise syntax: "lab", "none", or a comma-separated list whose first item may be
  /// "lab" or "none" (the default start is "none") followed by NAME=SIGMA items, NAME in vin_x,
  /// vin_y, win, vout_x, vout_y, wout, penetration, contact_duration (SI units), or "scale=F"
  /// multiplying everything set so far. Example: "lab,contact_duration=2e-4".
  /// Throws InputError (file "<command line>", field `option`) for a malformed spec.
  static NoiseSpec parse(const std::string& text, const std::string& option = "--noise");
  nlohmann::json to_json() const;

  /// The allowed range of every standard uncertainty (problems()): none is negative (0: exact).
  static constexpr OptionRange kSigma{0, INFINITY, false, true};
  /// The problems of this noise (common/option_problems.hpp), empty when it is valid.
  OptionProblems problems() const;
};

/// How incident states are drawn.
enum class Design {
  kLab,   ///< smoothed bootstrap of measured incident states (SynthOptions::incident)
  kWide,  ///< independent uniform draws over SynthOptions::wide
};
const char* design_name(Design design);

/// Box of the wide design (SI units). Default: V_in^x from 1.5 to 6 m/s, V_in^y from -5 to
/// -1 m/s, omega_in from -90 to 0 rad/s (top-spin, as every lab release): the lab ranges of
/// paper Table 2 roughly doubled.
struct WideBox {
  std::array<double, 2> vin_x{1.5, 6.0};    ///< [m/s]
  std::array<double, 2> vin_y{-5.0, -1.0};  ///< [m/s]
  std::array<double, 2> win{-90.0, 0.0};    ///< [rad/s]

  /// The problems of this box (common/option_problems.hpp), empty when it is valid: each range
  /// {LO, HI} finite with LO <= HI (LO = HI holds that component fixed), and vin_y's HI below 0
  /// (y is up: the block falls onto the ground). synthesize and design_throws
  /// (throw_design.hpp) call it at their entry.
  OptionProblems problems() const;
};

struct SynthOptions {
  std::size_t n = 30;      ///< releases to produce
  std::uint64_t seed = 1;  ///< seed of every random draw
  Design design = Design::kLab;
  /// Incident states resampled by the lab design (their vin only are used). Each true incident
  /// state is a randomly chosen one of them plus a Gaussian kernel perturbation with Silverman's
  /// bandwidth 1.06 s n^(-1/5) per component (s its sample standard deviation).
  ImpactSet incident;
  WideBox wide;
  NoiseSpec noise = NoiseSpec::lab();
  /// Per-release scatter of the truth: parameter NAME is drawn per release as
  /// N(truth value, SD^2), clipped to its bounds (release-to-release variability of the ground).
  std::vector<std::pair<std::string, double>> scatter;
  /// Orientation of non-disc blocks at contact: uniform over [min, max] [rad] (default one
  /// period of the 3-fold symmetric triangle, as fit::AlphaOptions).
  std::array<double, 2> alpha_range_rad{-M_PI / 3, M_PI / 3};
  /// Features written besides the velocities (as a LIGGGHTS run or an instrumented lab has them;
  /// the paper's lab has none of them). alpha_in only for non-disc shapes.
  bool write_alpha = true, write_penetration = true, write_contact_duration = true;
  /// Engine settings of the truth runs: the calibration's (bulk_engine_options).
  EngineOptions engine = bulk_engine_options();
  std::string id_prefix = "S";  ///< release ids: S001, S002, ...

  /// The allowed ranges (problems(); the command line shows kN in --help): one release at
  /// least, 1e7 bounds the set held in memory; a scatter SD is a standard deviation (kSigma);
  /// the orientation range lies within half a turn of 0, its min below its max.
  static constexpr OptionRange kN{1, 1e7};
  static constexpr OptionRange kSigma = NoiseSpec::kSigma;
  static constexpr OptionRange kAlphaRad{-M_PI, M_PI};
  /// The problems of these options (common/option_problems.hpp), empty when they are valid;
  /// noise's, wide's and engine's prefixed by the member ("wide.vin_y"). synthesize calls it at
  /// its entry.
  OptionProblems problems() const;
};

struct SynthResult {
  ImpactSet set;             ///< the measured set (no truth inside)
  std::size_t rejected = 0;  ///< draws redrawn: no rebound, or noise made vin_y >= 0 / vout_y <= 0
  /// The truth: model (effects, values), shape, options, per-release true parameter values and
  /// incident states. For provenance files only; the diagnosis never reads it.
  nlohmann::json truth;
};

/// Generates the set (see the file comment). Throws InputError for options with problems
/// (SynthOptions::problems: n = 0, negative noise or scatter, an empty box, ...), and
/// std::invalid_argument for a lab design without incident states or an unknown scatter
/// parameter (the truth model's).
SynthResult synthesize(const Model& truth, const Shape& shape, const SynthOptions& options);

/// The lab's measured incident states for a shape: data/lab/cylinders.csv or triangles.csv
/// in the data folder (common/paths.hpp: $RICOCHET_DATA_DIR, else share/ricochet/data beside the
/// program). Other shapes: the cylinders'.
ImpactSet lab_incident_states(const Shape& shape);

/// Extra columns written by synthesize() next to the penetration and contact duration: their
/// standard uncertainties (the schema's sigma columns cover V_in and V_out only). The noise
/// floor (diagnosis/noise.hpp) reads them.
inline constexpr const char* kSigmaPenetration = "sigma_penetration";
inline constexpr const char* kSigmaContactDuration = "sigma_contact_duration";

}  // namespace ricochet::diagnosis
