// EngineOptions::problems(): the one check of the engine's settings (engine.hpp).
#include "engine/engine.hpp"

namespace ricochet {

OptionProblems EngineOptions::problems() const {
  OptionProblems p;
  check_range(p, "dt_s", dt_s, kDt);
  check_range(p, "max_time_s", max_time_s, kMaxTime);
  check_range(p, "threads", threads, kThreads);
  check_range(p, "lanes", static_cast<double>(lanes), kLanes);
  return p;
}

}  // namespace ricochet
