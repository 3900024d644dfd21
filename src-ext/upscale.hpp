// Upscaling: the reduced engine's equivalent contact parameters (e_n^2, mu, mu_R of paper
// section 4.1, or any calibrated parameter of the model) fitted to resolved (LIGGGHTS) impacts,
// per impact and per set of grain-scale parameters, with the calibration module's identifiability
// (fit/fit.hpp), and how they vary with the grain-scale parameters and the incident state (the
// "abacuses" called for by the paper's conclusion).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "campaign_store.hpp"
#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "fit/fit.hpp"
#include "impact/impact_set.hpp"
#include "params.hpp"

namespace ricochet::dem {

struct UpscaleOptions {
  fit::FitOptions fit;
  /// Grain-scale parameters ("bed.NAME" / "block.NAME") that define the groups. Empty: every
  /// bed or block parameter that takes more than one value in the campaign (replica seeds
  /// excluded: replicas belong to one group).
  std::vector<std::string> by;
  std::string where;  ///< impact-set filter applied to the campaign's /impacts first
  /// Measured releases to compare with (already of the campaign's shape), or none. They are
  /// calibrated per release with the same model, shape and fit options (paper Eq. 7; their own
  /// noise is fit.sigma, the lab's operator scale, unless a release carries its own), so that the
  /// resolved and the measured equivalent parameters come from one engine: the paper's Table 4
  /// was fitted by another implementation and is not a like-for-like reference.
  const ImpactSet* lab = nullptr;
  /// Keep only the releases of `lab` whose ids the campaign's impacts (after `where`) carry: a
  /// campaign run at lab states compared with those releases, not with the whole lab
  /// (`upscale --lab-same-ids`). An InputError when none is left.
  bool lab_same_ids = false;
};

/// One resolved impact with its grain-scale parameters and its calibration.
struct UpscaleImpact {
  std::string id;
  std::string group;                         ///< key of its group
  std::map<std::string, std::string> grain;  ///< values of the grouping parameters
  fit::ReleaseFit fit;
};

/// Impacts sharing their grain-scale parameters (replicas, incident states).
struct UpscaleGroup {
  std::string key;  ///< "bed.E_grain_Pa=2e+08 block.mu_gb=0.5" (or "all")
  std::map<std::string, std::string> grain;
  std::vector<std::size_t> members;  ///< indices into UpscaleResult::impacts
  fit::PopulationFit population;     ///< one parameter set for the group
};

struct UpscaleResult {
  std::string source;  ///< the campaign file
  std::string shape;
  std::vector<std::string> by;  ///< the grouping parameters
  ImpactSet set;                ///< the calibrated impacts (one shape)
  std::vector<UpscaleImpact> impacts;
  std::vector<UpscaleGroup> groups;
  std::optional<fit::PopulationFit> campaign;  ///< over all impacts (when several groups)
  /// Measurement noise of a resolved V_out used by the identifiability intervals (m/s, m/s,
  /// rad/s), added in quadrature to each impact's reconstruction errors, and where it comes
  /// from: "replicates" (pooled scatter of replicate impacts, replicate_groups()) or "table1"
  /// (no replicates: the lab's operator scale, fit::FitOptions::sigma).
  Vel3 noise_sigma{};
  std::string noise_source;
  ImpactSet lab;                          ///< UpscaleOptions::lab (empty when none)
  std::vector<fit::ReleaseFit> lab_fits;  ///< its per-release calibrations, in its order
  double seconds = 0;
};

/// Reads the campaign's successful impacts (/impacts, the impact-set schema) and their specs
/// (/dem/index/params), keeps those of `shape`, groups them by grain-scale parameters and
/// calibrates `model` per impact and per group. Throws InputError naming the file when it is not
/// a campaign, has no successful impact of the shape, or `by` names an unknown parameter.
UpscaleResult upscale(const std::string& campaign_h5, const Decks& decks, const Model& model,
                      const Shape& shape, const UpscaleOptions& options);

/// Effective grain-scale parameters of each impact of a campaign file, by id: every bed.* and
/// block.* parameter of the decks with the impact's overrides applied (the seed included).
/// `index`: the file's /dem/index (read_campaign_index); `campaign_h5` names it in errors.
std::map<std::string, std::map<std::string, std::string>> campaign_grain_parameters(
    const std::string& campaign_h5, const std::vector<CampaignEntry>& index, const Decks& decks);

/// Figures (SVG, report/plot.hpp) into `dir`:
///   upscale_parameters.svg  the fitted parameters per impact against the incident speed
///                           |V_in| and the incident spin, by group;
///   upscale_abacus_<P>.svg  for each numeric grouping parameter P: each fitted parameter of
///                           the group fits (with its near-optimal interval) and of the
///                           impacts, against P;
///   upscale_vs_lab.svg      with lab releases: ECDFs of V_out of the resolved impacts and of
///                           the lab releases (paper Figs. 9-10 style);
///   upscale_parameters_vs_lab.svg  with lab releases: ECDFs of each calibrated parameter, per
///                           resolved impact and per lab release (one engine for both).
/// Returns the files written.
std::vector<std::string> write_upscale_figures(const UpscaleResult& result, const std::string& dir);

}  // namespace ricochet::dem
