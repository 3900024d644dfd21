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

/// The test bed: a 0.6 m x 0.06 m slab, 0.06 m deep, grains of 4-6 mm radius, grain parameters
/// of docs/resolved-model.md that give the cylinder a rebound. About 2,000 grains.
inline const std::vector<std::string> kTestBed = {"bed.Lx_m=0.6",   "bed.Ly_m=0.06",
                                                  "bed.H_m=0.06",   "bed.r1_m=0.004",
                                                  "bed.r2_m=0.005", "bed.r3_m=0.006"};

}  // namespace ricochet::dem::test
