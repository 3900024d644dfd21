// The force-residual discovery (issue 33, item 2): from the residual contact force of many
// releases' time series (measured force minus the reduced law's along the same path), find the
// few terms of a dimensioned library that explain it, with numbers, units, bootstrap intervals
// over releases and the literature law each term belongs to.
//
// The library, its frames and signs, and each term as an effect: effects/force_term.hpp (one
// table for the discovery and for the `term_<name>` effects that carry a discovered law into a
// model file).
//
// The selection is stats::sparse_regression (best subset by leak-free cross-validation over
// releases, cluster bootstrap): stats/sparse_regression.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "effects/force_term.hpp"
#include "stats/sparse_regression.hpp"

namespace ricochet::diagnosis {

using effects::component_name;
using effects::ContactSample;
using effects::force_terms;
using effects::ForceComponent;
using effects::ForceTerm;
using effects::kForceComponents;

/// The residual of one release: its samples and, per sample, the residual of each component
/// (NaN where a component was not measured: that component is then not analysed).
struct ReleaseResidual {
  std::vector<ContactSample> samples;
  std::vector<std::array<double, kForceComponents>> residual;
  std::vector<double> t_s;  ///< each sample's time [s] where known (force_residual), else empty
};

/// One discovered term, or one that was tried and not selected.
struct DiscoveredTerm {
  const ForceTerm* term = nullptr;
  double coefficient = 0;  ///< in term->unit; 0 when not selected
  /// Bootstrap percentile interval (stats::SparseOptions::level) of the coefficient, the law
  /// refitted on each resample of releases; NaN for a term not selected.
  double lo = 0, hi = 0;
  double inclusion = 0;  ///< how often the resamples' reselection picks it (stats::SparseResult)
  bool selected = false;
};

struct ComponentLaw {
  ForceComponent component = ForceComponent::kNormal;
  std::vector<DiscoveredTerm> terms;  ///< every term of the component, library order
  stats::SparseResult fit;            ///< the selection (grid, cross-validated errors)
  double rms_residual = 0;            ///< of the residual, in N or N m
  double heldout_rms = 0;             ///< of the residual minus the law's held-out prediction
  std::size_t releases = 0, samples = 0;
  /// The law in words with numbers and units, e.g. "F_n += -c v_n|v_n|, c = 41 kg/m [35, 47],
  /// in 98 % of resamples (Poncelet / Katsuragi-Durian drag)"; "nothing found" for the empty model,
  /// "no term named" for a component of a named law without a term.
  std::string text;
};

/// Finds the law of every component that has residuals. With `named` terms (a law the user
/// names, e.g. from a hypothesis or another set), each component fits exactly its named terms,
/// without selection (stats::SparseOptions::support), and a component without one fits none (its
/// text: "no term named"); ForceLawReport::named then says the law was fitted, not discovered.
/// Throws InputError for releases whose sizes disagree or that have non-finite states, or fewer
/// than two releases with samples.
std::vector<ComponentLaw> discover_force_law(const std::vector<ReleaseResidual>& releases,
                                             const stats::SparseOptions& options = {},
                                             std::span<const ForceTerm* const> named = {});

/// The library's terms of these names ("ploughing" or its effect name "term_ploughing"), in the
/// order given. Throws InputError (file `where`, field `field`) for an unknown name, listing the
/// library (effects::force_term_family_text), or a name given twice.
std::vector<const ForceTerm*> named_force_terms(const std::vector<std::string>& names,
                                                const std::string& where, const std::string& field);

}  // namespace ricochet::diagnosis
