#include "watchdog.h"

#include <algorithm>
#include <limits>

namespace REngine::sim {

StepWatchdog::StepWatchdog(double budgetSeconds, std::function<void()> expire) : m_expire(std::move(expire)) {
  // A budget beyond what the clock holds (a year is beyond any run) never fires.
  const double seconds = std::min(budgetSeconds, 3.0e7);
  m_budget = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds)) + kGrace;
  m_thread = std::thread([this] { Watch(); });
}

StepWatchdog::~StepWatchdog() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_changed.notify_all();
  m_thread.join();
}

void StepWatchdog::BeginStep() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_inStep = true, m_stepStart = Clock::now();
  }
  m_changed.notify_all();
}

void StepWatchdog::EndStep() {
  std::unique_lock<std::mutex> lock(m_mutex);
  // Fired: `expire` is ending the process from the watchdog's thread.
  if (m_fired) m_changed.wait(lock, [] { return false; });
  m_spent += Clock::now() - m_stepStart;
  m_inStep = false;
  lock.unlock();
  m_changed.notify_all();
}

void StepWatchdog::Watch() {
  std::unique_lock<std::mutex> lock(m_mutex);
  while (!m_stop) {
    if (!m_inStep) {
      m_changed.wait(lock, [this] { return m_stop || m_inStep; });
      continue;
    }
    const Clock::time_point deadline = m_stepStart + (m_budget - m_spent);
    const Clock::time_point start = m_stepStart;
    if (m_changed.wait_until(lock, deadline, [&] { return m_stop || !m_inStep || m_stepStart != start; })) continue;
    m_fired = true;
    lock.unlock();
    m_expire();
    return;
  }
}

}  // namespace REngine::sim
