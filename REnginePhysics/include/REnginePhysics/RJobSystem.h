// RJobSystem: how the step spreads its work over threads. The engine's own is RThreadPool;
// a game with a job system of its own implements RJobSystem and hands it to
// RIntegrator::SetJobSystem, so the physics shares the game's workers instead of competing
// with them.
//
// Determinism does not depend on it: the step splits its work into tasks whose outputs are
// kept apart and merged in a fixed order, so any thread count, any schedule and any job
// system give bit-identical results.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace REngine {

class RJobSystem {
 public:
  // One task: run(context, k) for task k. A plain function pointer and a context, so a call
  // costs no allocation; the engine makes one Run call per parallel stage, never one per pair.
  using RTask = void (*)(void* context, std::size_t k);

  virtual ~RJobSystem() = default;
  // How many threads may run tasks at once, the calling thread included (>= 1). The engine
  // cuts a stage into a few tasks per thread.
  virtual int ThreadCount() const = 0;
  // Runs task(context, k) for every k in [0, count), each exactly once, on any of its
  // threads (the caller's included), and returns when all have finished. Tasks of one Run
  // never share outputs; they may run in any order. A task that throws: RThreadPool still
  // runs the others, and Run throws the first exception once every task has finished.
  virtual void Run(std::size_t count, RTask task, void* context) = 0;
};

// The engine's job system: threads - 1 workers started once and kept, plus the caller. Run
// publishes the stage in one atomic word (which Run it is, and the next task to take) that
// every thread claims tasks from. A worker that finished a stage spins a short while for
// the next (a step's stages follow each other within microseconds, and waking a sleeping
// thread costs tens of them), then sleeps until a Run wakes it.
class RThreadPool final : public RJobSystem {
 public:
  // threads <= 0: std::thread::hardware_concurrency() (at least 1). When a worker cannot
  // be started, those already started are stopped and joined, and std::system_error is
  // thrown ("RThreadPool: could not start thread k of n: " and the system's reason; the
  // caller's thread is the first).
  explicit RThreadPool(int threads = 0);
  ~RThreadPool() override;
  RThreadPool(const RThreadPool&) = delete;
  RThreadPool& operator=(const RThreadPool&) = delete;

  int ThreadCount() const override { return static_cast<int>(m_workers.size()) + 1; }
  void Run(std::size_t count, RTask task, void* context) override;

  // What "what the machine has" means: hardware_concurrency, at least 1.
  static int MachineThreads();

 private:
  void WorkerLoop();
  void StopWorkers();  // wakes every worker to return, and joins them
  // Takes tasks of Run `run` (a generation) until none is left or another Run began.
  void Drain(std::uint32_t run);
  // Whether the word's Run is no longer `seen` (or the pool stops): a worker's wake-up.
  bool NewRun(std::uint32_t seen) const;

  std::vector<std::thread> m_workers;
  // The current Run: its generation in the high 32 bits, the next task to take in the low
  // 32; and its generation and task count the same way. A thread claims task k of Run g by
  // moving the word from (g, k) to (g, k + 1), and only then reads m_task and m_context:
  // Run g cannot return, nor the next Run write them, before task k has finished.
  std::atomic<std::uint64_t> m_word{0};
  std::atomic<std::uint64_t> m_countWord{0};
  std::atomic<std::size_t> m_finished{0};  // tasks of the current Run finished
  std::exception_ptr m_error;              // the current Run's first exception (under m_mutex)
  RTask m_task = nullptr;
  void* m_context = nullptr;
  std::uint32_t m_run = 0;  // the generation of the last Run (the caller's thread only)
  // Sleeping workers: they wait on m_wake under m_mutex, counted in m_sleepers so that a
  // Run takes the lock and notifies only when one sleeps. The caller, once its spin for the
  // last tasks is over, waits on m_done the same way (m_callerWaits).
  std::mutex m_mutex;
  std::condition_variable m_wake, m_done;
  std::atomic<int> m_sleepers{0};
  std::atomic<bool> m_callerWaits{false};
  std::atomic<bool> m_stop{false};
};

// Runs body(begin, end, task) over [0, count) cut into contiguous ranges, at most `tasks`
// of them and none of fewer than `grain` items (a stage too small to pay for waking threads
// runs inline, as one range), on the job system when there is one and more than one range.
// Returns how many ranges there were (0 for an empty range): task k's outputs are those of
// range k. The ranges depend only on count, tasks and grain, never on the threads.
// How many ranges ParallelRanges cuts [0, count) into: at most `tasks`, none of fewer than
// `grain` items (0 for an empty range).
inline std::size_t RangeCount(std::size_t count, std::size_t tasks, std::size_t grain) {
  if (count == 0) return 0;
  return std::min(tasks, std::max<std::size_t>(1, count / std::max<std::size_t>(1, grain)));
}

template <class Body>
std::size_t ParallelRanges(RJobSystem* jobs, std::size_t count, std::size_t tasks,
                           std::size_t grain, const Body& body) {
  if (count == 0) return 0;
  tasks = RangeCount(count, tasks, grain);
  if (!jobs || tasks <= 1) {
    body(std::size_t{0}, count, std::size_t{0});
    return 1;
  }
  struct Context {
    const Body* body;
    std::size_t count, tasks;
  } context{&body, count, tasks};
  jobs->Run(tasks, [](void* p, std::size_t k) {
    const Context& c = *static_cast<const Context*>(p);
    (*c.body)(c.count * k / c.tasks, c.count * (k + 1) / c.tasks, k);
  }, &context);
  return tasks;
}

}  // namespace REngine
