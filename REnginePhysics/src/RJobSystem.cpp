// RThreadPool: the engine's own job system (see RJobSystem.h).
#include <REnginePhysics/RJobSystem.h>

#include <algorithm>

namespace REngine {

int RThreadPool::MachineThreads() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

RThreadPool::RThreadPool(int threads) {
  const int n = threads > 0 ? threads : MachineThreads();
  m_workers.reserve(static_cast<std::size_t>(n - 1));
  for (int k = 1; k < n; ++k) m_workers.emplace_back([this] { WorkerLoop(); });
}

RThreadPool::~RThreadPool() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_wake.notify_all();
  for (std::thread& t : m_workers) t.join();
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
