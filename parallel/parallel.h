// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The one pool of worker threads that detection, rendering, the report and the
// solver's setup checks share: one image per worker in memory at a time.
// Internal (parallel/CMakeLists.txt).

#include <cstddef>
#include <functional>

namespace handeye::internal {

/// Calls `work(i)` once for every i in [0, count), on `threads` threads (0 =
/// all cores; never more than `count`, and the calling thread is one of
/// them). Items are taken in increasing order as workers become free, so
/// `work` must not depend on which thread runs it. After each item
/// `progress(done, count)` is called, if set, one call at a time. The first
/// exception stops the workers from taking further items and is rethrown
/// once all have stopped.
void ParallelFor(std::size_t count, int threads, const std::function<void(std::size_t)>& work,
                 const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace handeye::internal
