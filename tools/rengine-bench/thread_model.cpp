// The thread model of rengine-bench --scaling --model-threads (see thread_model.h).
#include "thread_model.h"

#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RJobSystem.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <limits>
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

bool ModelScene(const char* name, const RScene& scene, const std::vector<int>& threads, int repeats,
                const std::vector<MeasuredRow>& measured, std::uint64_t (*hash)(const RSceneWorld& world),
                std::vector<ModelRow>& out) {
  std::vector<std::vector<ThreadModel>> runs(threads.size());
  bool ok = true;
  for (int r = 0; r < repeats; ++r) {
    for (std::size_t k = 0; k < threads.size(); ++k) {
      runs[k].push_back(ModelThreads(scene, threads[k], hash));
      for (const MeasuredRow& m : measured) {
        if (m.hash != runs[k].back().hash) {
          std::printf("  error: %s: the run modelled on %d threads ended in another state (hash %016" PRIx64
                      ", measured %016" PRIx64 ")\n",
                      name, threads[k], runs[k].back().hash, m.hash);
          ok = false;
        }
      }
    }
  }
  for (std::size_t k = 0; k < runs.size(); ++k) {
    std::sort(runs[k].begin(), runs[k].end(), [](const ThreadModel& a, const ThreadModel& b) { return a.stepMs < b.stepMs; });
    ModelRow row;
    row.scene = name;
    row.model = runs[k][runs[k].size() / 2];
    row.measuredMs = std::numeric_limits<double>::quiet_NaN();
    for (const MeasuredRow& m : measured) {
      if (m.threads == threads[k]) row.measuredMs = m.ms;
    }
    out.push_back(row);
  }
  return ok;
}

bool PrintAndWriteModel(const std::vector<ModelRow>& rows, const std::string& path) {
  std::printf("\nthreads modelled from one thread's task times (thread_model.h): ms/step, speed-up over the first count, "
              "and this run's measured REngine ms/step where the machine has the threads\n");
  std::printf("%-17s %7s %10s %9s %9s %9s %7s %10s\n", "scene", "threads", "modelled", "speed-up", "serial",
              "work", "stages", "measured");
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f, "scene,threads,modelled_ms,speedup,serial_ms,work_ms,stages_per_step,measured_ms\n");
  double first = 0;
  const char* scene = nullptr;
  for (const ModelRow& r : rows) {
    if (r.scene != scene) scene = r.scene, first = r.model.stepMs;
    const double speedup = first / r.model.stepMs;
    std::printf("%-17s %7d %10.4g %9.3g %9.4g %9.4g %7.1f %10.4g\n", r.scene, r.model.threads, r.model.stepMs,
                speedup, r.model.serialMs, r.model.workMs, r.model.stagesPerStep, r.measuredMs);
    std::fprintf(f, "%s,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", r.scene, r.model.threads, r.model.stepMs, speedup,
                 r.model.serialMs, r.model.workMs, r.model.stagesPerStep, r.measuredMs);
  }
  return std::fclose(f) == 0;
}

}  // namespace rbench
