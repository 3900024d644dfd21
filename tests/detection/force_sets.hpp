// The force-residual data sets of the independent simulator (issue 33, item 4), shared by the
// test (force_discovery_test.cpp) and the study (force_discovery_study.cpp): 30 releases on the
// wide design per set, white force noise of sd 50 N on every force (an assumption: about 0.1 % of
// the ~50 kN peak contact force, not a measured track noise).
#pragma once

#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "diagnosis/force_law.hpp"
#include "truth_sim.hpp"

namespace ricochet::truth {

inline constexpr double kForceNoiseN = 50.0;

/// The hidden law's additive force along each release's own path (TraceSample::hidden_*), what a
/// perfect model of the paper's law would leave, plus the noise.
std::vector<diagnosis::ReleaseResidual> traced_set(Family f, double strength, std::uint64_t seed);

/// The user's path: the simulator's tracked history (PathSample, from before the contact; the
/// forces with the noise, no torque) minus the engine's paper law evaluated along it
/// (engine/path_force.hpp, diagnosis/force_residual.hpp) at the simulator's base parameters and
/// stiffnesses, as a well-calibrated base model would have them.
std::vector<diagnosis::ReleaseResidual> traced_set_through_law(Family f, double strength,
                                                               std::uint64_t seed);

/// The oracle's detection statistic on the set traced_set(f, strength, seed) makes (the same
/// releases, paths and noise): it knows the hidden force's exact shape along each path, g =
/// hidden force / strength in both components, and fits the one coefficient b of r = b g + noise
/// by least squares over every sample; z = b / SE(b), with SE(b) = s / sqrt(sum g^2) and s the
/// residuals' standard deviation. One pre-specified hypothesis, a known form and white noise: the
/// ceiling any search over a term library works under (the detection benchmark's oracle, for
/// force histories). Needs strength > 0.
double oracle_z(Family f, double strength, std::uint64_t seed);

/// The selected terms of every component, by name.
std::set<std::string> selected_terms(const std::vector<diagnosis::ComponentLaw>& laws);

/// Whether a term of `terms` (a family's) is among the selected terms of `laws`.
bool finds(const std::vector<diagnosis::ComponentLaw>& laws, const std::set<std::string>& terms);

/// traced_set or traced_set_through_law.
using SetMaker =
    std::function<std::vector<diagnosis::ReleaseResidual>(Family, double, std::uint64_t)>;

/// The law discovered on the set `make` gives for (f, strength, seed), the selection seeded with
/// the set's seed, no bootstrap (only the selection is read). Each component's law in words is
/// appended to *log ("seed S component: law").
std::vector<diagnosis::ComponentLaw> discover(const SetMaker& make, Family f, double strength,
                                              std::uint64_t seed, std::string* log = nullptr);

/// The sets, of seeds first .. first + n - 1, in which a term of `terms` is selected.
std::size_t sets_finding(const SetMaker& make, Family f, double strength,
                         const std::set<std::string>& terms, std::uint64_t first, std::size_t n,
                         std::string* log = nullptr);

}  // namespace ricochet::truth
