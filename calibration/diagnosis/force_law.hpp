// The force-residual discovery (issue 33, item 2): from the residual contact force of many
// releases' time series (measured force minus the reduced law's along the same path), find the
// few terms of a dimensioned library that explain it, with numbers, units, bootstrap intervals
// over releases and the literature law each term belongs to.
//
// Frames and signs: the contact frame of effects/effect.hpp. h >= 0 is the penetration [m],
// v_n the normal velocity of the contact point (< 0 into the ground) [m/s], v_t the sliding
// velocity [m/s], omega the block's spin [rad/s]. A residual component is a force on the block
// [N] (normal: > 0 pushes it out; tangential: along +t) or a moment [N m] (counter-clockwise > 0).
// Every term is neutral at a zero coefficient, and signed so that a positive coefficient
// resists the motion (a drag, a stiffening): a term's coefficient is then a physical constant
// whose sign says whether it is one.
//
// The library (the literature law each term is, where it is one):
//   normal:     h (Katsuragi & Durian 2007's k z; a linear spring), h^1.5 (Hertz), h^2,
//               -v_n|v_n| (Poncelet / Katsuragi-Durian inertial drag, coefficient m/d1 [kg/m]),
//               -v_n (viscous), -h v_n|v_n| (depth-growing drag), h sign(-v_n) (hysteresis:
//               a stiffer loading than unloading branch, Walton & Braun 1986)
//   tangential: -sign(v_x) h^2 (Rankine passive ploughing against the centre's motion, as the
//               catalog's `ploughing` effect: the sand ahead moves with the block, not with
//               the contact point's slip),
//               -sign(v_t) h, -v_t (viscous), -v_t|v_t| (inertial)
//   moment:     -sign(omega) h, -omega
// The selection is stats::sparse_regression (best subset by leak-free cross-validation over
// releases, cluster bootstrap): stats/sparse_regression.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "stats/sparse_regression.hpp"

namespace ricochet::diagnosis {

/// The contact's state at one sample of a time series (contact frame, SI).
struct ContactSample {
  double h_m = 0;          ///< penetration, >= 0
  double vn_mps = 0;       ///< normal velocity of the contact point, < 0 into the ground
  double vt_mps = 0;       ///< sliding velocity of the contact point
  double vx_mps = 0;       ///< the block centre's velocity along the tangent (what ploughs)
  double omega_radps = 0;  ///< the block's angular velocity
  bool loading = false;    ///< the penetration grows at this sample
};

/// Which residual a term explains.
enum class ForceComponent { kNormal = 0, kTangential = 1, kMoment = 2 };
inline constexpr std::size_t kForceComponents = 3;
std::string_view component_name(ForceComponent c);  ///< "normal", "tangential", "moment"

/// One term of the library (file comment).
struct ForceTerm {
  std::string_view name;  ///< e.g. "inertial_drag"
  ForceComponent component;
  std::string_view expression;  ///< e.g. "-c v_n|v_n|"
  std::string_view unit;        ///< SI unit of its coefficient c, e.g. "kg/m"
  std::string_view literature;  ///< the law it is, e.g. "Poncelet / Katsuragi-Durian drag"; "" none
  double (*value)(const ContactSample&);  ///< the term per unit coefficient, in N or N m
};

/// The library, in a fixed order.
const std::vector<ForceTerm>& force_terms();
/// The library's terms of one component, in library order.
std::vector<const ForceTerm*> force_terms(ForceComponent c);

/// The residual of one release: its samples and, per sample, the residual of each component
/// (NaN where a component was not measured: that component is then not analysed).
struct ReleaseResidual {
  std::vector<ContactSample> samples;
  std::vector<std::array<double, kForceComponents>> residual;
};

/// One discovered term, or one that was tried and not selected.
struct DiscoveredTerm {
  const ForceTerm* term = nullptr;
  double coefficient = 0;  ///< in term->unit; 0 when not selected
  double lo = 0, hi = 0;   ///< bootstrap percentile interval (stats::SparseOptions::level)
  double inclusion = 0;    ///< bootstrap frequency of its selection
  bool selected = false;
};

struct ComponentLaw {
  ForceComponent component = ForceComponent::kNormal;
  std::vector<DiscoveredTerm> terms;  ///< every term of the component, library order
  stats::SparseResult fit;            ///< the selection (grid, cross-validated errors)
  double rms_residual = 0;            ///< of the residual, in N or N m
  double heldout_rms = 0;             ///< of the residual minus the law's held-out prediction
  std::size_t releases = 0, samples = 0;
  /// The law in words with numbers and units, e.g. "F_n += -c v_n|v_n|, c = 41 kg/m [35, 47]
  /// (Poncelet / Katsuragi-Durian drag)"; "nothing found" for the empty model.
  std::string text;
};

/// Finds the law of every component that has residuals. Throws InputError for releases whose
/// sizes disagree or that have non-finite states, or fewer than two releases with samples.
std::vector<ComponentLaw> discover_force_law(const std::vector<ReleaseResidual>& releases,
                                             const stats::SparseOptions& options = {});

}  // namespace ricochet::diagnosis
