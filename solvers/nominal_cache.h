// The last error-free assembly a solver worked out, kept for the next scene: a campaign's
// scenes share one, and its static equilibrium (or linearisation) costs more than what
// each scene then adds to it.
#pragma once

#include <memory>
#include <mutex>
#include <utility>

#include "engine/scene.h"

namespace ringtol::solvers {

// One entry, keyed by the scene without its errors (Value::perfect). Thread-safe; the
// computation runs outside the lock, so two threads may both compute the same entry, and
// either result is the same.
template <typename Value>
class NominalCache {
 public:
  // The kept entry when its key is `perfect`, else compute(std::move(perfect)), which is
  // then kept.
  template <typename Compute>
  std::shared_ptr<const Value> Get(engine::Scene perfect, Compute&& compute) const {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (kept_ != nullptr && kept_->perfect == perfect) return kept_;
    }
    std::shared_ptr<const Value> value = std::forward<Compute>(compute)(std::move(perfect));
    const std::lock_guard<std::mutex> lock(mutex_);
    kept_ = value;
    return value;
  }

 private:
  mutable std::mutex mutex_;
  mutable std::shared_ptr<const Value> kept_;
};

}  // namespace ringtol::solvers
