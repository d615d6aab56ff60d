// RThreadPool: the engine's own job system (see RJobSystem.h).
#include <REnginePhysics/RJobSystem.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <system_error>

namespace REngine {

int RThreadPool::MachineThreads() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

RThreadPool::RThreadPool(int threads) {
  const int n = threads > 0 ? threads : MachineThreads();
  m_workers.reserve(static_cast<std::size_t>(n - 1));
  // A worker that cannot start (an address-space or thread limit) must not leave the ones
  // before it running: the members would then be destroyed under them (a condition
  // variable destroyed while threads wait on it blocks forever, a joinable thread ends the
  // program). They are stopped and joined, and the caller learns which thread failed.
  try {
    for (int k = 1; k < n; ++k) m_workers.emplace_back([this] { WorkerLoop(); });
  } catch (const std::system_error& e) {
    const std::size_t failed = m_workers.size() + 2;  // the caller's thread is the first
    StopWorkers();
    throw std::system_error(e.code(), "RThreadPool: could not start thread " + std::to_string(failed) +
                                          " of " + std::to_string(n));
  } catch (...) {
    StopWorkers();
    throw;
  }
}

RThreadPool::~RThreadPool() { StopWorkers(); }

namespace {

// One spin-wait iteration: tells the core this thread is waiting (x86 pause, Arm yield),
// which frees the pipeline for the other hardware thread and saves power.
inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__) || defined(__arm__)
  asm volatile("yield");
#endif
}

// How long a worker spins for the next Run before it sleeps, and how long the caller spins
// for the last tasks before it sleeps too. A step's stages come microseconds apart; a game's
// frame leaves milliseconds between steps, which the workers sleep through.
constexpr auto kWorkerSpin = std::chrono::microseconds(100);
constexpr auto kCallerSpin = std::chrono::microseconds(50);

constexpr std::uint32_t Generation(std::uint64_t word) { return static_cast<std::uint32_t>(word >> 32); }
constexpr std::uint32_t Low(std::uint64_t word) { return static_cast<std::uint32_t>(word); }

}  // namespace

void RThreadPool::StopWorkers() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_wake.notify_all();
  for (std::thread& t : m_workers) t.join();
  m_workers.clear();
}

bool RThreadPool::NewRun(std::uint32_t seen) const {
  return m_stop.load() || Generation(m_word.load()) != seen;
}

void RThreadPool::Drain(std::uint32_t run) {
  std::uint64_t word = m_word.load(std::memory_order_acquire);
  for (;;) {
    if (Generation(word) != run) return;
    // The count is read under the same generation: a stale one (the word moved on to the
    // next Run) is never used.
    const std::uint64_t countWord = m_countWord.load(std::memory_order_acquire);
    if (Generation(countWord) != run || Low(word) >= Low(countWord)) return;
    if (!m_word.compare_exchange_weak(word, word + 1, std::memory_order_acq_rel, std::memory_order_acquire)) continue;
    // Task Low(word) of this Run is ours: the Run waits for it, so m_task and m_context
    // stay this Run's until it finishes. An exception is kept for the caller (the first
    // one); the task counts as finished either way, so the Run still ends.
    try {
      m_task(m_context, Low(word));
    } catch (...) {
      std::lock_guard<std::mutex> lock(m_mutex);
      if (!m_error) m_error = std::current_exception();
    }
    const std::uint64_t count = Low(m_countWord.load(std::memory_order_relaxed));
    if (m_finished.fetch_add(1) + 1 == count && m_callerWaits.load()) {
      // The caller sleeps on m_done: notified under the lock it tests under.
      { std::lock_guard<std::mutex> lock(m_mutex); }
      m_done.notify_all();
    }
    word = m_word.load(std::memory_order_acquire);
  }
}

void RThreadPool::WorkerLoop() {
  std::uint32_t seen = 0;
  for (;;) {
    // Spin a while for the next Run, then sleep until one wakes this worker.
    const auto until = std::chrono::steady_clock::now() + kWorkerSpin;
    for (std::uint32_t k = 1; !NewRun(seen); ++k) {
      CpuRelax();
      if (k % 64 == 0 && std::chrono::steady_clock::now() > until) break;
    }
    if (!NewRun(seen)) {
      std::unique_lock<std::mutex> lock(m_mutex);
      // Counted before the test under the lock: a Run that publishes after the test sees
      // the sleeper and notifies under the same lock, so no wake-up is lost.
      m_sleepers.fetch_add(1);
      m_wake.wait(lock, [&] { return NewRun(seen); });
      m_sleepers.fetch_sub(1);
    }
    if (m_stop.load()) return;
    seen = Generation(m_word.load(std::memory_order_acquire));
    Drain(seen);
  }
}

void RThreadPool::Run(std::size_t count, RTask task, void* context) {
  if (count == 0) return;
  if (m_workers.empty()) {  // (as on several threads: every task runs, the first exception after)
    std::exception_ptr error;
    for (std::size_t k = 0; k < count; ++k) {
      try {
        task(context, k);
      } catch (...) {
        if (!error) error = std::current_exception();
      }
    }
    if (error) std::rethrow_exception(error);
    return;
  }
  if (count > 0xffffffffu) {  // more tasks than the word counts: in Runs of 2^32 - 1
    struct Part {
      RTask task;
      void* context;
      std::size_t offset;
    };
    for (std::size_t first = 0; first < count; first += 0xffffffffu) {
      Part part{task, context, first};
      Run(std::min<std::size_t>(count - first, 0xffffffffu), [](void* p, std::size_t k) {
        const Part& q = *static_cast<const Part*>(p);
        q.task(q.context, q.offset + k);
      }, &part);
    }
    return;
  }
  // Every task of the previous Run has finished: nobody reads m_task or m_context now.
  const std::uint32_t run = ++m_run;
  m_task = task, m_context = context;
  m_finished.store(0, std::memory_order_relaxed);
  m_countWord.store(std::uint64_t{run} << 32 | count, std::memory_order_release);
  m_word.store(std::uint64_t{run} << 32);  // sequentially consistent: see WorkerLoop
  if (m_sleepers.load() > 0) {
    { std::lock_guard<std::mutex> lock(m_mutex); }
    m_wake.notify_all();
  }
  Drain(run);
  // The last tasks, on other threads, end soon: spin a while, then sleep until the thread
  // that finishes the last one wakes this one.
  const auto until = std::chrono::steady_clock::now() + kCallerSpin;
  for (std::uint32_t k = 1; m_finished.load(std::memory_order_acquire) != count; ++k) {
    CpuRelax();
    if (k % 64 == 0 && std::chrono::steady_clock::now() > until) {
      std::unique_lock<std::mutex> lock(m_mutex);
      // Set before the test under the lock: a task that finishes after the test sees it and
      // notifies under the same lock, so the wake-up is not lost.
      m_callerWaits.store(true);
      m_done.wait(lock, [&] { return m_finished.load() == count; });
      m_callerWaits.store(false);
      break;
    }
  }
  std::exception_ptr error;
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    std::swap(error, m_error);
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace REngine
