// EngineOptions::problems(): the one check of the engine's settings (engine.hpp).
#include "engine/engine.hpp"

namespace ricochet {

OptionProblems EngineOptions::problems() const {
  OptionProblems p;
  check_range(p, "dt_s", dt_s, kDt);
  check_range(p, "max_time_s", max_time_s, kMaxTime);
  return p;
}

}  // namespace ricochet
