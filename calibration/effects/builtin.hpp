// Factories of the built-in effects, one per file effects/<name>.cpp. The registry
// (effects/registry.cpp) lists them explicitly: no self-registering static objects, which vanish
// when the library is linked statically.
#pragma once

#include <memory>

#include "effects/effect.hpp"

namespace ricochet::effects {

// The paper's law (Garcia et al. 2020, Eq. 3, 5, 6).
std::unique_ptr<Effect> make_normal();
std::unique_ptr<Effect> make_tangential();
std::unique_ptr<Effect> make_rolling();

// Candidate missing physics (docs/effects/README.md, one page each), one per family.
std::unique_ptr<Effect> make_rate_restitution();
std::unique_ptr<Effect> make_inertial_drag();
std::unique_ptr<Effect> make_ploughing();
std::unique_ptr<Effect> make_depth_friction();
std::unique_ptr<Effect> make_hertz_stiffness();

}  // namespace ricochet::effects
