// RThreadPool: the engine's own job system (see RJobSystem.h).
#include <REnginePhysics/RJobSystem.h>

#include <algorithm>
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

void RThreadPool::StopWorkers() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_wake.notify_all();
  for (std::thread& t : m_workers) t.join();
  m_workers.clear();
}

void RThreadPool::Drain() {
  // Tasks are handed out one at a time under the lock: a stage is cut into a few tasks per
  // thread, each of many bodies or pairs, so the lock is taken a few dozen times per stage.
  std::unique_lock<std::mutex> lock(m_mutex);
  while (m_next < m_count) {
    const std::size_t k = m_next++;
    const RTask task = m_task;
    void* context = m_context;
    lock.unlock();
    task(context, k);
    lock.lock();
    if (++m_finished == m_count) m_done.notify_all();
  }
}

void RThreadPool::WorkerLoop() {
  std::uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(m_mutex);
      m_wake.wait(lock, [&] { return m_stop || m_generation != seen; });
      if (m_stop) return;
      seen = m_generation;
    }
    Drain();
  }
}

void RThreadPool::Run(std::size_t count, RTask task, void* context) {
  if (count == 0) return;
  if (m_workers.empty()) {
    for (std::size_t k = 0; k < count; ++k) task(context, k);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_task = task, m_context = context;
    m_count = count, m_next = 0, m_finished = 0;
    ++m_generation;
  }
  m_wake.notify_all();
  Drain();
  std::unique_lock<std::mutex> lock(m_mutex);
  m_done.wait(lock, [&] { return m_finished == m_count; });
  // Nothing of this Run is left for a late worker: m_next == m_count.
}

}  // namespace REngine
