// Lock-step execution of many sequential searches so that their collisions share vectorised
// engine batches (internal to the fit module).
//
// Why: a derivative-free optimiser asks for one collision at a time, and one collision alone
// runs the engine on one lane (about 45 us for a cylinder on this machine), while a batch of 16
// or more runs at about 12 us per collision (engine/engine.hpp: SoA lanes). Calibrating 28
// releases with 4 starts each and then walking 6 interval sides per release gives hundreds of
// independent sequential searches. Each runs on its own stackful coroutine (POSIX ucontext);
// when every runnable search is waiting for a collision, the pool runs all requested collisions
// in ONE simulate_batch call and resumes them in creation order.
//
// Determinism: a search sees only its own results, the engine's result for a case does not
// depend on the batch (engine.hpp), and the pool resumes coroutines in a fixed order, so the
// results do not depend on how searches are grouped, nor on thread counts.
#pragma once

#include <cstddef>
#include <exception>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"

namespace ricochet::fit::detail {

/// Where the calibration code gets its collisions from.
class Simulator {
 public:
  virtual ~Simulator() = default;
  /// Results of `cases` with per-case parameter rows (or one shared row).
  virtual std::vector<CollisionResult> run(std::span<const CollisionCase> cases,
                                           std::span<const double> params) = 0;
  /// Runs independent tasks; a pool runs them in lock-step, the default one after the other.
  virtual void parallel(std::vector<std::function<void()>>& tasks) {
    for (auto& t : tasks) t();
  }
};

/// Calls the engine directly (simulate() for one case, simulate_batch() otherwise).
class DirectSimulator final : public Simulator {
 public:
  DirectSimulator(const Model& model, const Shape& shape, const EngineOptions& options)
      : model_(model), shape_(shape), options_(options) {}
  std::vector<CollisionResult> run(std::span<const CollisionCase> cases,
                                   std::span<const double> params) override;

 private:
  const Model& model_;
  const Shape& shape_;
  EngineOptions options_;
};

/// Coroutine pool; see the file comment. Not thread-safe: one pool per thread.
class FiberPool final : public Simulator {
 public:
  /// `options` for the merged batches (its `lanes` bounds the SoA width, `threads` the engine's
  /// OpenMP threads per batch).
  FiberPool(const Model& model, const Shape& shape, const EngineOptions& options,
            std::size_t stack_bytes = 512 * 1024);
  ~FiberPool() override;
  FiberPool(const FiberPool&) = delete;
  FiberPool& operator=(const FiberPool&) = delete;

  /// Adds a coroutine running `body`; `on_finish` runs on the pool's own stack when it ends
  /// (e.g. writing results to a file). Call before run_all() or from inside a coroutine.
  void spawn(std::function<void()> body, std::function<void()> on_finish = {});
  /// Inside a coroutine: yields until the collisions are done (batched with all others).
  /// Outside: runs them directly.
  std::vector<CollisionResult> run(std::span<const CollisionCase> cases,
                                   std::span<const double> params) override;
  /// Inside a coroutine: runs the tasks as child coroutines and waits for all of them; rethrows
  /// the first child's exception. Outside: one after the other.
  void parallel(std::vector<std::function<void()>>& tasks) override;
  /// Runs every coroutine to its end; rethrows the first exception of a top-level coroutine.
  void run_all();

  std::size_t batches() const { return batches_; }
  std::size_t collisions() const { return collisions_; }

 private:
  struct Fiber;
  static void entry(unsigned lo, unsigned hi);
  void resume(Fiber* f);
  void yield(Fiber* f);

  const Model& model_;
  const Shape& shape_;
  EngineOptions options_;
  std::size_t stack_bytes_;
  std::vector<std::unique_ptr<Fiber>> fibers_;
  Fiber* current_ = nullptr;
  struct MainContext;
  std::unique_ptr<MainContext> main_;
  std::size_t batches_ = 0, collisions_ = 0;
};

}  // namespace ricochet::fit::detail
