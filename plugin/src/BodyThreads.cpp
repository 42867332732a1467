// SPDX-License-Identifier: Zlib
// The threads of the controller's parallel phase (BodyThreads.hpp).
#include "BodyThreads.hpp"

#include <LinearMath/btThreads.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>

namespace hydrotex::bullet {
namespace {

/// The user's Bullet task scheduler when it runs more than one thread, else null.
btITaskScheduler* bulletScheduler() {
  btITaskScheduler* scheduler = btGetTaskScheduler();
  return scheduler != nullptr && scheduler->getNumThreads() > 1 ? scheduler : nullptr;
}

/// Cores this process may run on (its affinity mask and cgroup quota included).
int cores() { return std::max(1, tbb::info::default_concurrency()); }

/// Hands Bullet's scheduler one call per body.
class ForEachBody final : public btIParallelForBody {
 public:
  explicit ForEachBody(const std::function<void(std::size_t)>& work) : work_(work) {}
  void forLoop(int begin, int end) const override {
    for (int i = begin; i < end; ++i) work_(std::size_t(i));
  }

 private:
  const std::function<void(std::size_t)>& work_;
};

}  // namespace

struct BodyThreads::Arena {
  explicit Arena(int threads) : arena(threads) {}
  tbb::task_arena arena;
};

BodyThreads::BodyThreads(int requested) : requested_(requested) {}

BodyThreads::~BodyThreads() = default;

bool BodyThreads::followsBullet() const { return requested_ == 0 && bulletScheduler() != nullptr; }

int BodyThreads::threads() const {
  if (requested_ == 0) {
    if (btITaskScheduler* scheduler = bulletScheduler()) return scheduler->getNumThreads();
    return cores();
  }
  // More threads than cores would only take turns; oneTBB would not start them either unless the
  // first arena of the process asked for them, so the count used is capped here, predictably.
  return std::clamp(requested_, 1, cores());
}

void BodyThreads::forEach(std::size_t count, const std::function<void(std::size_t)>& work) {
  const int threads = this->threads();
  if (threads <= 1 || count <= 1) {
    for (std::size_t i = 0; i < count; ++i) work(i);
    return;
  }
  if (btITaskScheduler* scheduler = requested_ == 0 ? bulletScheduler() : nullptr) {
    // The scheduler itself, not btParallelFor: a Bullet built without BT_THREADSAFE (Debian's)
    // makes btParallelFor a plain loop whatever scheduler is set, while a threadsafe one just
    // forwards to it. Grain 1: a body's work is far larger than a task's cost.
    scheduler->parallelFor(0, int(count), 1, ForEachBody(work));
    return;
  }
  if (!arena_ || arena_->arena.max_concurrency() != threads) arena_ = std::make_unique<Arena>(threads);
  arena_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) work(i);
    });
  });
}

}  // namespace hydrotex::bullet
