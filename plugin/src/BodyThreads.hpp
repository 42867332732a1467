// SPDX-License-Identifier: Zlib
// The threads of the controller's parallel phase: one call per body, on a oneTBB task arena of the
// requested size or on the user's Bullet task scheduler. Private to the plugin.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace hydrotex::bullet {

/// Runs work(i) for i in [0, count) on up to threads() threads. Each i is called exactly once and
/// the calls share nothing through this class, so results do not depend on the thread count.
class BodyThreads {
 public:
  /// `requested`: ControllerSettings::threads (0: all cores, or the Bullet task scheduler's
  /// threads when the user set one with more than one thread; >= 1: that many, at most the cores).
  explicit BodyThreads(int requested);
  ~BodyThreads();
  BodyThreads(const BodyThreads&) = delete;
  BodyThreads& operator=(const BodyThreads&) = delete;

  /// Threads the next forEach runs on (>= 1).
  int threads() const;
  /// True when the next forEach goes through Bullet's btITaskScheduler rather than oneTBB.
  bool followsBullet() const;
  /// Calls work(i) once for every i in [0, count); returns when all calls have returned.
  void forEach(std::size_t count, const std::function<void(std::size_t)>& work);

 private:
  struct Arena;  // a tbb::task_arena, kept out of this header (oneTBB is a private dependency)
  int requested_;
  std::unique_ptr<Arena> arena_;  ///< made on first use with more than one thread
};

}  // namespace hydrotex::bullet
