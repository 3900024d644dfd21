// The picture of a resolved impact (impact/impact_snapshot.hpp) as a figure: a strip of frames
// through the contact, side view, grains of the section as discs coloured by speed (one colour
// scale for every frame), the block's spheres in grey (their union is the block's outline).
#pragma once

#include <string>

#include "impact/impact_snapshot.hpp"
#include "report/plot.hpp"

namespace ricochet::report {

/// One panel per frame, titled with its time since first contact [ms] (the deepest one marked).
/// Axes in millimetres; colour scale from 0 to the largest grain speed of the frames [m/s].
/// Throws std::invalid_argument for a snapshot without frames.
Figure impact_picture(const ImpactSnapshot& snapshot, const std::string& title);

}  // namespace ricochet::report
