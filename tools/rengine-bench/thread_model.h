// rengine-bench --scaling --model-threads: REngine's step on thread counts this machine may
// not have, modelled from one thread's timings. The step runs on one thread with its parallel
// stages cut as they are for P threads (RJobSystem::ThreadCount() says P), every task timed;
// each stage's tasks are then dealt as RThreadPool deals them (the next task to the thread
// that is free first) onto P modelled threads. The step's modelled time is its time outside
// the stages plus every stage's span on P threads.
//
// What it leaves out: a thread's wake-up and the claim of a task (about a microsecond a
// stage on RThreadPool, spinning), and the memory the threads share (caches, bandwidth), which
// make real threads slower than their tasks timed alone. Where the machine has the threads,
// the measured rows beside it show how far apart the two are.
#pragma once

#include <REnginePhysics/RScene.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rbench {

struct ThreadModel {
  int threads = 1;
  double stepMs = 0;        // modelled ms per step on `threads` threads
  double serialMs = 0;      // of which outside the parallel stages (the same on any count)
  double workMs = 0;        // the stages' tasks, summed (one thread's time in them)
  double stagesPerStep = 0; // parallel stages (RJobSystem::Run calls) a step
  std::uint64_t hash = 0;   // the final state's, by the caller's hash: the same as the pool's
};

// One run of the scene (its steps, its settings but the thread count), timed as above.
ThreadModel ModelThreads(const REngine::RScene& scene, int threads,
                         std::uint64_t (*hash)(const REngine::RSceneWorld& world));

// --model-threads, per scene: the model on each thread count (medians of `repeats` runs,
// the counts interleaved) beside the measured REngine rows of the same run. Returns false
// when a modelled run ended in another state than the measured ones (reported): its stages
// ran on one thread, cut for more, and must give the same state to the bit.
struct MeasuredRow {
  int threads = 1;
  double ms = 0;  // per step
  std::uint64_t hash = 0;
};
struct ModelRow {
  const char* scene = nullptr;
  ThreadModel model;
  double measuredMs = 0;  // NaN where the run has no row on as many threads
};
bool ModelScene(const char* name, const REngine::RScene& scene, const std::vector<int>& threads, int repeats,
                const std::vector<MeasuredRow>& measured, std::uint64_t (*hash)(const REngine::RSceneWorld& world),
                std::vector<ModelRow>& out);
// The table (printed) and the CSV at `path`: each scene's step on P threads, its speed-up
// over the first count given (1 when it is listed first). False when the CSV cannot be written.
bool PrintAndWriteModel(const std::vector<ModelRow>& rows, const std::string& path);

}  // namespace rbench
