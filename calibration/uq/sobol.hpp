// Sobol sensitivity indices (Garcia et al. 2020, section 4.4, Figs. 17-18, Appendix B Eq. B1-B4)
// of the reflected velocities to the model parameters, computed by OpenTURNS:
//   design    SobolIndicesExperiment (Saltelli's pick-freeze design with second order: N (2d + 2)
//             model runs for d inputs and base size N), seeded;
//   estimators SaltelliSensitivityAlgorithm, JansenSensitivityAlgorithm,
//             MartinezSensitivityAlgorithm or MauntzKucherenkoSensitivityAlgorithm;
//   intervals  first and total order: OpenTURNS' bootstrap (resampling the N rows of the
//             design), percentile intervals at `confidence`; second order: the same bootstrap,
//             calling the same OpenTURNS estimator on each resampled design.
// Indices are reported as estimated: small negative values (estimation noise around zero) are
// kept, with their intervals, never clipped.
//
// The paper used one-factor-at-a-time sampling (section 4.4); these are the variance-based
// indices its Appendix B defines.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/option_problems.hpp"
#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"
#include "uq/distribution.hpp"

namespace ricochet::uq {

enum class SobolEstimator { kSaltelli, kJansen, kMartinez, kMauntzKucherenko };
const char* estimator_name(SobolEstimator e);
/// "saltelli", "jansen", "martinez", "mauntz-kucherenko"; throws std::invalid_argument otherwise.
SobolEstimator parse_estimator(const std::string& name);

struct SobolOptions {
  std::size_t base_size = 4096;  ///< N; the model runs N (2d + 2) times
  std::uint64_t seed = 1;
  SobolEstimator estimator = SobolEstimator::kSaltelli;
  std::size_t bootstrap = 200;  ///< bootstrap resamples for the intervals
  double confidence = 0.95;     ///< level of the bootstrap percentile intervals

  /// The allowed ranges (problems(); the command line shows them in --help). base_size: 16 at
  /// least for the estimators' rows, 1e8 bounds the design held in memory; bootstrap: a
  /// percentile interval needs two resamples at least (OpenTURNS refuses none); confidence: a
  /// level, strictly between 0 and 1.
  static constexpr OptionRange kBaseSize{16, 1e8};
  static constexpr OptionRange kBootstrap{2, 1e6};
  static constexpr OptionRange kConfidence{0, 1, true, true};
  /// The problems of these options (common/option_problems.hpp), empty when they are valid;
  /// sobol_indices and collision_sobol call it at their entry.
  OptionProblems problems() const;
};

/// An index with its bootstrap interval.
struct Index {
  double value = 0, lo = 0, hi = 0;
};

/// Indices per output: first[o][i], total[o][i], second[o][i][j] (i < j filled, symmetric).
struct SobolResult {
  std::vector<std::string> inputs, outputs;
  std::vector<std::vector<Index>> first, total;
  std::vector<std::vector<std::vector<Index>>> second;
  std::size_t base_size = 0, evaluations = 0;
  std::string estimator;
  double confidence = 0;
  double seconds = 0;
  /// Output variance per output (indices are fractions of it); 0 makes indices undefined.
  std::vector<double> variance;
  /// The design actually run: evaluations x inputs and evaluations x outputs, row-major, in
  /// OpenTURNS' block order (A, B, then the pick-freeze blocks).
  std::vector<double> design_x, design_y;
};

/// Generic: a vectorised model Y = f(X) (X: n x d row-major, Y: n x outputs row-major) with
/// independent inputs. Used for the Ishigami check and by the collision model below.
using BatchFunction =
    std::function<void(const std::vector<double>& x, std::size_t n, std::vector<double>& y)>;
SobolResult sobol_indices(const BatchFunction& f, const std::vector<ParameterInput>& inputs,
                          const std::vector<std::string>& outputs, const SobolOptions& options);

/// The collision model: outputs vx, vy, w of V_out for the incident state `vin` (orientation
/// `alpha_rad` for non-disc blocks) when the `inputs` parameters vary (others at model values).
/// Runs go to simulate_batch (parallel, vectorised) in one call. Options with problems (the
/// engine's prefixed "engine.") are refused with InputError before the design is drawn.
SobolResult collision_sobol(const Model& model, const Shape& shape,
                            const std::vector<ParameterInput>& inputs, const Vel3& vin,
                            double alpha_rad, const SobolOptions& options,
                            const EngineOptions& engine = {});

/// Ishigami function f = sin x1 + a sin^2 x2 + b x3^4 sin x1 on [-pi, pi]^3 (Ishigami & Homma
/// 1990) and its analytic indices (Sobol & Levitan 1999), for the verification test.
struct IshigamiIndices {
  double first[3], total[3], second13;
};
IshigamiIndices ishigami_analytic(double a = 7.0, double b = 0.1);
BatchFunction ishigami(double a = 7.0, double b = 0.1);

}  // namespace ricochet::uq
