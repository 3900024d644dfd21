// The transfer module's output layer: the results of `ricochet transfer fit` and `transfer
// predict` as JSON, CSV, HDF5, text and SVG figures, in one place (docs/commands/transfer.md lists
// every key and column). The commands only choose what to compute and which of these to write.
//
// Velocities are (V^x [m/s], V^y [m/s], omega [rad/s]) in the impact-set frame
// (impact/impact_set.hpp); A and dA are dimensionless (paper Eq. 2).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/option_problems.hpp"
#include "impact/impact_set.hpp"
#include "transfer/transfer.hpp"

namespace ricochet::transfer {

/// Everything `transfer fit` computes on one (filtered) impact set.
struct FitReport {
  std::string where;  ///< the filter that made the set ("" = all releases)
  std::size_t n = 0;  ///< releases
  DiagonalFit diagonal;
  std::optional<FullFit> full;           ///< absent when the 3x3 fit is not identifiable
  std::optional<LooComparison> loo;      ///< absent when there are too few releases
  std::string full_reason, loo_reason;   ///< why full / loo are absent
  std::vector<Vel3> in, out, predicted;  ///< incident, measured and Eq. 2-sampled reflected
  DistributionComparison ks;             ///< measured against predicted V_out
  std::uint64_t seed = 0;                ///< of the predicted samples
  std::size_t replicates = 0;            ///< predicted rebounds per release
};

/// How `transfer fit` samples Eq. 2 for its KS comparison and its figures.
struct FitSampling {
  std::uint64_t seed = 1;        ///< of the predicted samples
  std::size_t replicates = 100;  ///< predicted rebounds per release
  /// The allowed range of replicates (problems(); the command line shows it in --help): one
  /// rebound per release at least; 1e7 bounds the samples held in memory.
  static constexpr OptionRange kReplicates{1, 1e7};
  /// The problems of these options (common/option_problems.hpp), empty when they are valid;
  /// analyse_fit calls it at its entry.
  OptionProblems problems() const;
};

/// Fits Eq. 2, the full matrix and their leave-one-out comparison on `set`, samples
/// `sampling.replicates` rebounds per release with `sampling.seed`, and compares them with the
/// measured V_out.
FitReport analyse_fit(const ImpactSet& set, const std::string& where,
                      const FitSampling& sampling = {});

/// JSON of one fit: "where", "n", "A", "dA", "moments", "full" (or null and
/// "full_unavailable"), "loo" (or null and "loo_unavailable"), "ks".
nlohmann::json to_json(const FitReport& report);
/// One row per component: A, dA, moments, the full matrix's row and standard errors, the LOO
/// RMSEs and the KS statistic and p-value. `source` names the impact set in the header.
void write_fit_csv(const std::string& path, const std::string& source, const FitReport& report);
/// The model (read back by `transfer predict --model`) and the comparisons, under /transfer.
void write_fit_h5(const std::string& path, const std::string& source, const FitReport& report);
/// The text table the command prints.
std::string format_fit(const std::string& source, const FitReport& report);
/// One row of a CDF figure: incident, measured reflected and predicted velocities.
struct CdfRow {
  std::string label;
  const std::vector<Vel3>* in;
  const std::vector<Vel3>* out;
  const std::vector<Vel3>* predicted;
};
/// An SVG figure with one row of three ECDF panels (V^x, V^y, omega) per CdfRow (paper
/// Figs. 11-12: incident grey, measured reflected black, Eq. 2 green).
void write_cdf_figure(const std::string& path, const std::string& title,
                      const std::vector<CdfRow>& rows);

/// Everything `transfer predict` computes: `replicates` samples per incident state, in order
/// (samples[i * replicates + r] belongs to incident i).
struct PredictReport {
  DiagonalModel model;
  nlohmann::json model_source;   ///< where the model came from ("file", "source", "where", "n")
  std::vector<std::string> ids;  ///< one per incident state
  std::vector<Vel3> vin, samples;
  std::size_t replicates = 0;
  std::uint64_t seed = 0;
  std::optional<DistributionComparison> ks;  ///< against the measured V_out, with --incident
  std::size_t nonphysical_vy = 0;            ///< samples with V_out^y <= 0
};

/// Where `transfer predict`'s incident states come from.
enum class PredictIncidents {
  kGivenState,   ///< one state given (--vin): its reflected distribution is what is asked for
  kMeasuredSet,  ///< the measured states of a set (--incident), each with its measured rebound
};

/// How `transfer predict` samples Eq. 2.
struct PredictSampling {
  std::uint64_t seed = 0;  ///< of the random stream (the command line requires it)
  /// Predicted rebounds per incident state; unset: replicates_for's default.
  std::optional<std::size_t> replicates;
  /// The defaults: a given state's distribution is drawn with many rebounds; each state of a
  /// measured set with one, so that the predicted sample is as large as the measured one it is
  /// compared with (KS).
  static constexpr std::size_t kGivenStateReplicates = 1000;
  static constexpr std::size_t kMeasuredSetReplicates = 1;
  /// The allowed range of replicates (problems(); the command line shows it in --help): transfer
  /// fit's, the same samples held in memory.
  static constexpr OptionRange kReplicates = FitSampling::kReplicates;
  /// The replicates asked for, or the default of `incidents`.
  std::size_t replicates_for(PredictIncidents incidents) const;
  /// The problems of these options (common/option_problems.hpp), empty when they are valid;
  /// sample_predictions calls it at its entry.
  OptionProblems problems() const;
};

/// Samples `sampling.replicates_for(incidents)` rebounds of `report.model` per incident state
/// of `report.vin` with `sampling.seed`: fills report.samples, replicates, seed and
/// nonphysical_vy. Options with problems are refused with InputError before any draw.
void sample_predictions(PredictReport& report, PredictIncidents incidents,
                        const PredictSampling& sampling);

/// JSON keys: "seed", "model", "incidents", "replicates", "n_samples", "summary",
/// "nonphysical_vy", "ks" (with measurements), "samples" (null above 10,000).
nlohmann::json to_json(const PredictReport& report);
/// One row per sample: incident id, replicate, V_in and V_out with units in the header.
void write_predict_csv(const std::string& path, const PredictReport& report);
/// /predict/{vin, vout (n x 3), incident, A, dA} with seed, replicates and units attributes.
void write_predict_h5(const std::string& path, const PredictReport& report);
std::string format_predict(const PredictReport& report);

}  // namespace ricochet::transfer
