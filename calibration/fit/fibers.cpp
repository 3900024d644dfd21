#include "fit/fibers.hpp"

#include <ucontext.h>

#include <cstdint>
#include <stdexcept>

namespace ricochet::fit::detail {

std::vector<CollisionResult> DirectSimulator::run(std::span<const CollisionCase> cases,
                                                  std::span<const double> params) {
  if (cases.size() == 1) return {simulate(model_, shape_, cases[0], params, options_)};
  return simulate_batch(model_, shape_, cases, params, options_);
}

struct FiberPool::MainContext {
  ucontext_t ctx;
};

struct FiberPool::Fiber {
  enum class State { kReady, kRequest, kJoin, kDone };
  FiberPool* pool = nullptr;
  ucontext_t ctx;
  std::unique_ptr<char[]> stack;
  std::function<void()> body, on_finish;
  Fiber* parent = nullptr;
  int live_children = 0;
  std::exception_ptr child_error;
  State state = State::kReady;
  bool started = false;
  // Pending request (spans point into the coroutine's own, suspended, frame).
  std::span<const CollisionCase> cases;
  std::span<const double> params;
  std::vector<CollisionResult> results;
  std::exception_ptr error;
};

FiberPool::FiberPool(const Model& model, const Shape& shape, const EngineOptions& options,
                     std::size_t stack_bytes)
    : model_(model),
      shape_(shape),
      options_(options),
      stack_bytes_(stack_bytes),
      main_(std::make_unique<MainContext>()) {}

FiberPool::~FiberPool() = default;

void FiberPool::spawn(std::function<void()> body, std::function<void()> on_finish) {
  auto f = std::make_unique<Fiber>();
  f->pool = this;
  f->body = std::move(body);
  f->on_finish = std::move(on_finish);
  f->parent = current_;
  if (current_) ++current_->live_children;
  fibers_.push_back(std::move(f));
}

void FiberPool::entry(unsigned lo, unsigned hi) {
  auto* f = reinterpret_cast<Fiber*>((static_cast<std::uintptr_t>(hi) << 32) |
                                     static_cast<std::uintptr_t>(lo));
  // Exceptions must not leave the coroutine's stack: keep them for the scheduler.
  try {
    f->body();
  } catch (...) {
    f->error = std::current_exception();
  }
  f->state = Fiber::State::kDone;
  if (f->parent) {
    --f->parent->live_children;
    if (f->error && !f->parent->child_error) f->parent->child_error = f->error;
  }
  // Returning switches to uc_link: the scheduler.
}

void FiberPool::resume(Fiber* f) {
  if (!f->started) {
    f->started = true;
    // Uninitialised storage: pages are committed only as the coroutine's stack grows.
    f->stack.reset(new char[stack_bytes_]);
    if (getcontext(&f->ctx) != 0) throw std::runtime_error("getcontext failed");
    f->ctx.uc_stack.ss_sp = f->stack.get();
    f->ctx.uc_stack.ss_size = stack_bytes_;
    f->ctx.uc_link = &main_->ctx;
    const auto p = reinterpret_cast<std::uintptr_t>(f);
    makecontext(&f->ctx, reinterpret_cast<void (*)()>(&FiberPool::entry), 2,
                static_cast<unsigned>(p & 0xffffffffu), static_cast<unsigned>(p >> 32));
  }
  Fiber* saved = current_;
  current_ = f;
  swapcontext(&main_->ctx, &f->ctx);
  current_ = saved;
  if (f->state == Fiber::State::kDone) {
    f->stack.reset();
    if (f->on_finish) f->on_finish();
  }
}

void FiberPool::yield(Fiber* f) {
  swapcontext(&f->ctx, &main_->ctx);
}

std::vector<CollisionResult> FiberPool::run(std::span<const CollisionCase> cases,
                                            std::span<const double> params) {
  if (!current_) return DirectSimulator(model_, shape_, options_).run(cases, params);
  Fiber* f = current_;
  f->cases = cases;
  f->params = params;
  f->state = Fiber::State::kRequest;
  yield(f);
  return std::move(f->results);
}

void FiberPool::parallel(std::vector<std::function<void()>>& tasks) {
  if (!current_) {
    for (auto& t : tasks) t();
    return;
  }
  Fiber* f = current_;
  for (auto& t : tasks) spawn(t);
  f->state = Fiber::State::kJoin;
  yield(f);
  if (f->child_error) {
    std::exception_ptr e = f->child_error;
    f->child_error = nullptr;
    std::rethrow_exception(e);
  }
}

void FiberPool::run_all() {
  const std::size_t P = model_.parameter_count();
  std::vector<CollisionCase> cases;
  std::vector<double> params;
  std::vector<Fiber*> waiting;
  while (true) {
    // Advance every runnable coroutine to its next request (children spawned during this pass
    // are appended and reached in the same pass).
    for (std::size_t i = 0; i < fibers_.size(); ++i) {
      Fiber* f = fibers_[i].get();
      if (f->state == Fiber::State::kJoin && f->live_children == 0) f->state = Fiber::State::kReady;
      if (f->state == Fiber::State::kReady) resume(f);
    }
    waiting.clear();
    cases.clear();
    params.clear();
    bool joinable = false;
    for (auto& up : fibers_) {
      Fiber* f = up.get();
      if (f->state == Fiber::State::kJoin && f->live_children == 0) joinable = true;
      if (f->state != Fiber::State::kRequest) continue;
      waiting.push_back(f);
      cases.insert(cases.end(), f->cases.begin(), f->cases.end());
      // Expand a shared parameter row so that the merged batch has one row per case.
      if (f->params.size() == P * f->cases.size()) {
        params.insert(params.end(), f->params.begin(), f->params.end());
      } else {
        for (std::size_t c = 0; c < f->cases.size(); ++c)
          params.insert(params.end(), f->params.begin(), f->params.end());
      }
    }
    if (waiting.empty()) {
      if (joinable) continue;
      break;  // every coroutine is done
    }
    const auto results = simulate_batch(model_, shape_, cases, params, options_);
    ++batches_;
    collisions_ += cases.size();
    std::size_t at = 0;
    for (Fiber* f : waiting) {
      f->results.assign(results.begin() + at, results.begin() + at + f->cases.size());
      at += f->cases.size();
      f->state = Fiber::State::kReady;
    }
  }
  for (auto& up : fibers_) {
    if (up->state != Fiber::State::kDone)
      throw std::logic_error("fiber pool: a coroutine never finished (join without children?)");
    if (!up->parent && up->error) std::rethrow_exception(up->error);
  }
}

}  // namespace ricochet::fit::detail
