// Shared by the resolved-model tests: the shipped decks, and the small test bed every LIGGGHTS
// test uses (the same parameters, hence the same cached bed).
#pragma once

#include <string>
#include <vector>

#include "params.hpp"

namespace ricochet::dem::test {

/// The decks of liggghts-inputs/ in the source tree.
inline const Decks& decks() {
  static const Decks d = Decks::locate(std::string(RICOCHET_SOURCE_DIR) + "/liggghts-inputs");
  return d;
}

/// The test bed: a 0.6 m x 0.06 m slab, 0.06 m deep, grains of 4-6 mm radius, and the grain law
/// of set H (docs/resolved-model.md; the decks' defaults until the calibrated bed replaced them),
/// pinned so that the tests' expectations do not move with the defaults. About 2,000 grains.
inline const std::vector<std::string> kTestBed = {
    "bed.Lx_m=0.6",   "bed.Ly_m=0.06",  "bed.H_m=0.06",       "bed.r1_m=0.004",
    "bed.r2_m=0.005", "bed.r3_m=0.006", "bed.E_grain_Pa=2e8", "bed.e_gg=0.7",
    "bed.mu_gg=0.8",  "bed.mur_gg=0.5", "bed.mu_pour=0.1",    "bed.rolling_model=epsd2",
    "block.mu_gb=0.5",  "block.mur_gb=0.1"};

}  // namespace ricochet::dem::test
