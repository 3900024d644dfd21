// Collisions already simulated, shared by the fits of one assessment (issue 35, item 3).
//
// The fold fits of a leak-free assessment start from the same data-free design (the model's
// nominal values and one Latin hypercube), and a release's collisions at a design point do not
// depend on which fold it trains: the engine is deterministic. The same holds for each BOBYQA
// start's first 2d + 1 points (Problem::eval_starts), which follow from the start and the initial
// step alone; the folds mostly pick the same starts. The first fit that simulates them stores
// them; the others read them. A key is a collision's exact inputs and a result is the engine's,
// so a fit through the memo gives its answer without the memo bit for bit, and nothing of a
// fold's held-out releases enters it. The searches' later points are not kept: they follow the
// fold's data, so another fit rarely meets them, and they are most of a fit's collisions.
#pragma once

#include <cstddef>
#include <mutex>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"

namespace ricochet::fit {

namespace detail {
class Simulator;
}

class CollisionMemo {
 public:
  /// `scope` names what the results hold for besides a collision's inputs (the model's effects,
  /// the shape, the engine settings): a fit whose scope differs must not use this memo.
  explicit CollisionMemo(std::string scope) : scope_(std::move(scope)) {}
  const std::string& scope() const { return scope_; }

  /// The results of `cases` (parameters per case: `per_case` values each, row-major in
  /// `params`), those already known from the memo, the others run by `sim` in one batch and
  /// stored. Thread-safe; the engine runs outside the lock.
  std::vector<CollisionResult> run(detail::Simulator& sim, std::span<const CollisionCase> cases,
                                   std::span<const double> params, std::size_t per_case);

  std::size_t hits() const;    ///< collisions read from the memo so far
  std::size_t stored() const;  ///< collisions held

 private:
  std::string scope_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, CollisionResult> results_;
  std::size_t hits_ = 0;
};

/// The scope string of a fit of `model` on `shape` with `engine` (CollisionMemo::scope): the
/// effects, the shape and the engine's physical settings (not its threads or lanes, which do
/// not change a result).
std::string collision_memo_scope(const Model& model, const Shape& shape,
                                 const EngineOptions& engine);

}  // namespace ricochet::fit
