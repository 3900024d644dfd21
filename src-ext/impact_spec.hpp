// What one resolved impact is, and how its velocities are extracted: the plain types a campaign
// design is made of. Kept free of MPI and LIGGGHTS so that the design reader (campaign_design.cpp)
// compiles on its own (the fuzz target fuzz/fuzz_campaign_toml.cpp builds it with clang).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "impact/impact_set.hpp"
#include "params.hpp"

namespace ricochet::dem {

/// One impact of a campaign (paper frame: x flight direction, y up, omega > 0 counter-clockwise).
struct ImpactSpec {
  std::string id;
  std::string shape = "cylinder";  ///< "cylinder", "triangle" or a shape file (.toml)
  Vel3 vin{2.9, -2.3, -65.0};      ///< incident state at first contact (m/s, m/s, rad/s)
  double alpha_in_rad = 0;         ///< incident orientation
  /// Replica seed: bed seed and block insertion seed become the (2 seed + 1)-th and
  /// (2 seed + 2)-th primes above 10000. Absent: the decks' seeds (or explicit overrides).
  std::optional<std::int64_t> seed;
  Overrides params;  ///< bed / block / run parameter overrides
};

/// How V_in and V_out are extracted from the block's track.
struct ExtractOptions {
  /// Frame rate of the track given to the reconstruction [1/s]: the lab camera's 400 fps by
  /// default (like with like); 0 = every recorded state.
  double fps = 400;
  /// Contact window given to the reconstruction: "force" (default; the DEM analogue of the
  /// operator's "the block touches the sand": contact force above f_contact_frac x weight while
  /// the block is within two grain radii of the surface), "ground" = the paper's geometric
  /// criterion (centre within the contact radius of the levelled surface, Fig. 8b; fails when the
  /// block leaves from the bottom of its crater), "auto" = the reconstruction's ballistic-residual
  /// detection. Empty = force.
  std::string window;
};

}  // namespace ricochet::dem
