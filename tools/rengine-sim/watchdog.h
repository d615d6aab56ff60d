// StepWatchdog: --max-seconds within a step. The run's budget is checked between steps
// (main.cpp), which a step that never ends (a scene asking for the most solver iterations on
// a large joint island, a machine far slower than expected) would never reach; this thread
// watches the step itself and, once the stepping time passes the budget by kGrace, calls
// `expire` from its own thread (which must end the process: the step it interrupts cannot
// be finished). The step's thread is then held in EndStep, so that it never touches what
// `expire` closes.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace REngine::sim {

class StepWatchdog {
 public:
  using Clock = std::chrono::steady_clock;
  // How far past the budget a step may run before it is stopped inside: a step that ends
  // within it is stopped after, by the check between steps, with its rows.
  static constexpr std::chrono::seconds kGrace{1};

  StepWatchdog(double budgetSeconds, std::function<void()> expire);
  ~StepWatchdog();
  StepWatchdog(const StepWatchdog&) = delete;
  StepWatchdog& operator=(const StepWatchdog&) = delete;

  void BeginStep();
  void EndStep();

 private:
  void Watch();
  std::mutex m_mutex;
  std::condition_variable m_changed;
  Clock::duration m_budget;
  Clock::duration m_spent{};  // stepping time of the finished steps
  Clock::time_point m_stepStart;
  bool m_inStep = false, m_stop = false, m_fired = false;
  std::function<void()> m_expire;
  std::thread m_thread;
};

}  // namespace REngine::sim
