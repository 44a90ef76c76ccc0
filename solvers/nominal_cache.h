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
  // The kept entry when its key is engine::WithoutErrors(scene), else
  // compute(engine::WithoutErrors(scene)), which is then kept. A hit builds no scene: the
  // key is compared field by field with what `scene` keeps of itself without errors
  // (engine::SameWithoutErrors), every sample of a campaign, outside the lock (an entry
  // is never modified once kept).
  template <typename Compute>
  std::shared_ptr<const Value> Get(const engine::Scene& scene, Compute&& compute) const {
    std::shared_ptr<const Value> kept;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      kept = kept_;
    }
    if (kept != nullptr && engine::SameWithoutErrors(kept->perfect, scene)) return kept;
    std::shared_ptr<const Value> value = std::forward<Compute>(compute)(engine::WithoutErrors(scene));
    const std::lock_guard<std::mutex> lock(mutex_);
    kept_ = value;
    return value;
  }

 private:
  mutable std::mutex mutex_;
  mutable std::shared_ptr<const Value> kept_;
};

}  // namespace ringtol::solvers
