// The thread model of rengine-bench --scaling --model-threads (see thread_model.h).
#include "thread_model.h"

#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RJobSystem.h>

#include <algorithm>
#include <chrono>
#include <vector>

using namespace REngine;

namespace rbench {

namespace {

using Clock = std::chrono::steady_clock;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

// A job system that says it has P threads and runs every task on the caller's, timing each,
// and deals each stage's tasks onto P modelled threads in RThreadPool's order: task k goes
// to the thread that is free first (the lowest-numbered of those tied), as the first thread
// to come back claims the next task from the shared counter.
class TaskRecorder final : public RJobSystem {
 public:
  explicit TaskRecorder(int threads) : m_threads(threads), m_free(static_cast<std::size_t>(threads)) {}
  int ThreadCount() const override { return m_threads; }
  void Run(std::size_t count, RTask task, void* context) override {
    std::fill(m_free.begin(), m_free.end(), 0.0);
    const Clock::time_point start = Clock::now();
    Clock::time_point before = start;
    for (std::size_t k = 0; k < count; ++k) {
      task(context, k);
      const Clock::time_point after = Clock::now();
      const double ms = Ms(after - before);
      before = after;
      *std::min_element(m_free.begin(), m_free.end()) += ms;
      work += ms;
    }
    span += *std::max_element(m_free.begin(), m_free.end());
    inStages += Ms(before - start);
    ++stages;
  }

  double span = 0, inStages = 0, work = 0;  // ms, over the run
  std::size_t stages = 0;

 private:
  int m_threads;
  std::vector<double> m_free;  // each modelled thread's busy time in the current stage, ms
};

}  // namespace

ThreadModel ModelThreads(const RScene& scene, int threads, std::uint64_t (*hash)(const RSceneWorld& world)) {
  RSceneWorld world(scene);
  RIntegrator integrator(scene.settings);
  TaskRecorder recorder(threads);
  integrator.SetJobSystem(&recorder);
  const Clock::time_point t0 = Clock::now();
  for (std::uint64_t s = 0; s < scene.steps; ++s) integrator.Update(world.Bodies(), scene.dt);
  const double total = Ms(Clock::now() - t0);
  const double steps = static_cast<double>(scene.steps);
  ThreadModel m;
  m.threads = threads;
  m.serialMs = (total - recorder.inStages) / steps;
  m.stepMs = m.serialMs + recorder.span / steps;
  m.workMs = recorder.work / steps;
  m.stagesPerStep = static_cast<double>(recorder.stages) / steps;
  m.hash = hash(world);
  return m;
}

}  // namespace rbench
