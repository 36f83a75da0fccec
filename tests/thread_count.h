// Runs work on exactly `threads` TBB threads (more than the machine's cores included), so that a test
// can require the same result whatever the thread count.
#pragma once
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

namespace isoatlas::test {

template <class F>
auto onThreads(int threads, F work) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
  tbb::task_arena arena(threads);
  return arena.execute(work);
}

}  // namespace isoatlas::test
