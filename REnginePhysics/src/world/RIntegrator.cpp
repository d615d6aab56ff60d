// RIntegrator::Update, the step as a table of contents: the stamp, CollisionDetection (pair
// sweep, contact solver with its joint solver), UpdateObjects (the motion, sleeping), the
// contact events. The subsystems are RWorldStep's members, each owning its state behind its
// own header (docs/ARCHITECTURE.md, "Subsystems and folders", lists the folders and files);
// each gets what it reads of the others here, as parameters.
#include <REnginePhysics/RIntegrator.h>

#include "world/RWorldStep.h"

#include <REngineMath/RQuaternion.h>

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace REngine {

std::uint64_t NextCacheStamp() {
  static std::atomic<std::uint64_t> s_stamp{0};
  return ++s_stamp;
}

RScalar Combine(RCombineMode mode, RScalar a, RScalar b) {
  switch (mode) {
    case RCombineMode::kMin: return std::min(a, b);
    case RCombineMode::kMax: return std::max(a, b);
    case RCombineMode::kProduct: return a * b;
    case RCombineMode::kAverage: return RScalar(0.5) * (a + b);
    case RCombineMode::kGeometric: return std::sqrt(a * b);
  }
  return a;
}


namespace {
using Clock = std::chrono::steady_clock;
double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }
}  // namespace



RIntegrator::RIntegrator() : RIntegratorCore{std::make_unique<RWorldStep>()} {}
RIntegrator::RIntegrator(const RWorldSettings& settings) : RIntegrator() {
  m_w->m_settings = settings;
}
RIntegrator::~RIntegrator() = default;
RIntegrator::RIntegrator(const RIntegrator& other)
    : RIntegratorCore{std::make_unique<RWorldStep>(*other.m_w)}, m_gameJobs(other.m_gameJobs) {}
RIntegrator& RIntegrator::operator=(const RIntegrator& other) {
  if (this != &other) *m_w = *other.m_w, m_gameJobs = other.m_gameJobs;
  return *this;
}
RIntegrator::RIntegrator(RIntegrator&&) noexcept = default;
RIntegrator& RIntegrator::operator=(RIntegrator&&) noexcept = default;

void RIntegrator::ForgetContacts() {
  m_w->m_solver.ForgetWarmStarts(), m_w->m_sweep.ForgetManifolds(), m_w->m_sleep.WakeAllNextStep();
}
const RWorldSettings& RIntegrator::Settings() const { return m_w->m_settings; }
RWorldSettings& RIntegrator::Settings() { return m_w->m_settings; }
const RStepProfile& RIntegrator::Profile() const { return m_w->m_profile; }
std::uint64_t RIntegrator::StepCount() const { return m_w->m_stepCount; }
std::uint64_t RIntegrator::CacheStamp() const { return m_w->m_cacheStamp; }
const std::optional<RNonFiniteBody>& RIntegrator::NonFinite() const {
  return m_w->m_motion.NonFinite();
}
const std::vector<RNonFiniteBody>& RIntegrator::NonFiniteInLastStep() const {
  return m_w->m_motion.NonFiniteInLastStep();
}
const std::vector<RContact>& RIntegrator::Contacts() const { return m_w->m_sweep.Contacts(); }
const std::vector<RContactEvent>& RIntegrator::Events() const { return m_w->m_eventLog.Events(); }
RBodyContactEvents RIntegrator::EventsOf(RBodyHandle body) const { return m_w->m_eventLog.EventsOf(body); }
RContactEventSpan RIntegrator::EventsBetween(RBodyHandle a, RBodyHandle b) const {
  return m_w->m_eventLog.EventsBetween(a, b);
}
const RPairStats& RIntegrator::PairStats() const { return m_w->m_sweep.Stats(); }
void RIntegrator::SetJobSystem(RJobSystem* jobs) { m_gameJobs = jobs; }

void RIntegrator::PrepareJobs() {
  RWorldStep& w = *m_w;
  if (w.m_settings.threads < 0 || w.m_settings.threads > RWorldSettings::kMaxThreads) {
    const std::string problem = "must be 0 (what the machine has) to " +
                                std::to_string(RWorldSettings::kMaxThreads) + " (got " +
                                std::to_string(w.m_settings.threads) + ")";
    throw RError("threads", problem, "RIntegrator::Update: RWorldSettings::threads " + problem);
  }
  if (w.m_settings.solverIterations < 1 || w.m_settings.solverIterations > RWorldSettings::kMaxSolverIterations) {
    const std::string problem = "must be 1 to " + std::to_string(RWorldSettings::kMaxSolverIterations) +
                                " (got " + std::to_string(w.m_settings.solverIterations) + ")";
    throw RError("solverIterations", problem, "RIntegrator::Update: RWorldSettings::solverIterations " + problem);
  }
  for (const RCombineMode mode : {w.m_settings.restitutionCombine, w.m_settings.frictionCombine}) {
    if (static_cast<std::uint8_t>(mode) > static_cast<std::uint8_t>(RCombineMode::kGeometric)) {
      const std::string problem = "must be an RCombineMode (got " + std::to_string(static_cast<int>(mode)) + ")";
      throw RError(mode == w.m_settings.restitutionCombine ? "restitutionCombine" : "frictionCombine", problem,
                   "RIntegrator::Update: RWorldSettings::restitutionCombine and frictionCombine " + problem);
    }
  }
  // The numbers the step divides by, compares with and multiplies into every body: a NaN or
  // a negative one would silently disable what it controls (a NaN threshold bounces
  // nothing), so they are refused here, as the scene loader refuses them.
  auto refuse = [](const char* field, const std::string& requirement, RScalar got) {
    const std::string problem = "must be " + requirement + " (got " + std::to_string(got) + ")";
    throw RError(field, problem, std::string("RIntegrator::Update: RWorldSettings::") + field + " " + problem);
  };
  const RWorldSettings& s = w.m_settings;
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(s.gravity_W[k])) refuse("gravity_W", "finite", s.gravity_W[k]);
  }
  const struct {
    const char* field;
    RScalar value;
  } nonNegative[] = {{"restitutionThreshold", s.restitutionThreshold}, {"penetrationSlop", s.penetrationSlop},
                     {"positionCorrection", s.positionCorrection},
                     {"maxPositionCorrection", s.maxPositionCorrection}, {"sleepSpeed", s.sleepSpeed},
                     {"sleepTime", s.sleepTime}};
  // (As a saved state's settings are read: RStateStep.cpp.)
  for (const auto& [field, value] : nonNegative) {
    if (!(std::isfinite(value) && value >= 0)) refuse(field, "finite and >= 0", value);
  }
  RJobSystem* jobs = m_gameJobs;
  if (!jobs) {
    const int threads = w.m_settings.threads > 0 ? w.m_settings.threads : RThreadPool::MachineThreads();
    if (threads > 1) {
      if (!m_pool || m_pool->ThreadCount() != threads) m_pool = std::make_unique<RThreadPool>(threads);
      jobs = m_pool.get();
    } else {
      m_pool.reset();
    }
  }
  // A few tasks per thread, so that a thread that drew a light range takes another. The
  // count changes only how the work is cut, never its result.
  const int threads = jobs ? jobs->ThreadCount() : 1;
  w.m_jobs = threads > 1 ? jobs : nullptr;
  w.m_tasks = threads > 1 ? static_cast<std::size_t>(4 * threads) : 1;
}

void RIntegrator::SetContactCallback(RContactCallback callback, void* user) {
  m_w->m_materials.SetCallback(callback, user);
}

void RIntegrator::SetPairFilter(RPairFilter filter, void* user) {
  m_w->m_sweep.SetPairFilter(filter, user), m_w->m_sleep.WakeAllNextStep();
}

namespace {
void CheckDt(RScalar dt) {
  if (!(std::isfinite(dt) && dt > 0 && dt <= RIntegrator::kMaxDt)) {
    char text[96];
    std::snprintf(text, sizeof text, "at most %g s (got %.17g)", RIntegrator::kMaxDt, dt);
    const std::string problem = std::string("must be finite, > 0 and ") + text;
    throw RError("dt", problem, "RIntegrator::Update: dt " + problem);
  }
}
}  // namespace

void RIntegrator::Update(RBodies& bodies, RScalar dt) {
  CheckDt(dt);
  RStepBodies view;
  view.data = Core(bodies).m_slots.items.data();
  view.count = Core(bodies).m_enabled;
  view.handles = Core(bodies).m_slots.handles.data();
  view.denseOfSlot = Core(bodies).m_slots.denseOfSlot.data();
  view.slotCount = Core(bodies).m_slots.denseOfSlot.size();
  view.byIndex = false;
  view.wakeIslands = &Core(bodies).m_wakeIslands;
  view.wakeAll = &Core(bodies).m_wakeAll;
  view.wakeBoxes = &Core(bodies).m_wakeBoxes;
  view.joints = Core(bodies).m_jointSlots.items.data();
  view.jointCount = Core(bodies).m_jointSlots.items.size();
  view.noCollidePairs = Core(bodies).m_noCollide.data();
  view.noCollideCount = Core(bodies).m_noCollide.size();
  // Queries' caches of the poses (RQueries) see the bodies moved, also when the step throws
  // part way.
  Core(bodies).m_poseStamp.Bump();
  Step(view, dt);
  Core(bodies).m_poseStamp.Bump();
}

void RIntegrator::Update(std::vector<RRigidBody>& bodies, RScalar dt) {
  CheckDt(dt);
  const std::size_t n = bodies.size();
  // Identity by position: body i is slot i, generation 0 (filled once per size).
  std::vector<RBodyHandle>& handles = m_w->m_indexHandles;
  std::vector<std::uint32_t>& slots = m_w->m_indexSlots;
  for (std::size_t i = handles.size(); i < n; ++i) {
    handles.push_back(RBodyHandle{static_cast<std::uint32_t>(i), 0});
    slots.push_back(static_cast<std::uint32_t>(i));
  }
  RStepBodies view;
  view.data = bodies.data();
  view.count = n;
  view.handles = handles.data();
  view.denseOfSlot = slots.data();
  view.slotCount = n;
  view.byIndex = true;
  Step(view, dt);
}

void RIntegrator::Step(const RStepBodies& bodies, RScalar dt) {
  RWorldStep& w = *m_w;
  const auto t0 = Clock::now();
  PrepareJobs();  // before anything moves: a bad setting throws with the world untouched
  w.m_cacheStamp = NextCacheStamp();
  ++w.m_stepCount;
  w.m_sleep.WakeIslands(bodies, w.m_settings);
  CollisionDetection(bodies, dt);
  const auto t1 = Clock::now();
  // The contact events compare the poses before and after.
  w.m_eventLog.KeepStartPoses(bodies, w.m_settings.contactEvents, w.m_jobs, w.m_tasks);
  UpdateObjects(bodies, dt);
  const auto t2 = Clock::now();
  // Contact events: begin, persist, end, from the contacts and the motion (RContactEvents.h).
  const RContactEventLog::RStepInputs events{w.m_settings.contactEvents, w.m_sweep.Contacts(),
                                             w.m_solver.IslandImpacts(), w.m_solver.BlockIslands(),
                                             w.m_sweep.PassiveFlags(), w.m_jobs, w.m_tasks};
  w.m_eventLog.FindContactEvents(bodies, events, w.m_solver.Impacts());
  // The bodies moved: a new stamp, so world forms that detection cached at the old poses
  // are recomputed when game code asks after the step.
  w.m_cacheStamp = NextCacheStamp();
  const auto t3 = Clock::now();
  w.m_profile.collisionDetection = Ms(t1 - t0) - w.m_profile.findImpulses;
  w.m_profile.updateObjects = Ms(t2 - t1);
  w.m_profile.contactEvents = Ms(t3 - t2);
  w.m_profile.total = Ms(t3 - t0);
}

void RIntegrator::CollisionDetection(const RStepBodies& bodies, RScalar dt) {
  RWorldStep& w = *m_w;
  std::uint64_t wakeRuns = 0;
  // A sweep that touched a sleeping island wakes it and runs again: the woken bodies' pairs
  // with each other, skipped while they slept, must be found too. Each rerun wakes at least
  // one island, so this ends.
  const RPairSweep::RStepInputs sweep{w.m_settings, w.m_jobs, w.m_tasks, w.m_cacheStamp};
  while (w.m_sweep.DetectPairs(bodies, dt, sweep, w.m_broad, w.m_sleep)) {
    w.m_sleep.WakeMarked(bodies);
    ++wakeRuns;
  }
  w.m_sweep.MutableStats().wakeRuns = wakeRuns;
  const auto t0 = Clock::now();
  w.m_materials.Prepare(bodies, w.m_sweep.Contacts(), w.m_settings);
  const RContactSolver::RSolverInputs solver{w.m_settings, w.m_sweep, w.m_welds, w.m_jobs, w.m_tasks, w.m_materials};
  w.m_solver.FindImpulses(bodies, dt, solver);
  w.m_profile.findImpulses = Ms(Clock::now() - t0);
}

void RIntegrator::UpdateObjects(const RStepBodies& bodies, RScalar dt) {
  RWorldStep& w = *m_w;
  const RMotion::RStepInputs motion{w.m_settings, w.m_welds, w.m_solver.Solved(), w.m_solver.InRows(),
                                    w.m_stepCount, w.m_jobs, w.m_tasks};
  w.m_motion.Integrate(bodies, dt, motion, w.m_solver.SolverBodies(), w.m_solver.MutableWarmStarts());
  w.m_sweep.MutableStats().sleepingBodies =
      w.m_sleep.SleepIslands(bodies, w.m_settings, w.m_sweep.Contacts(), w.m_sweep.BodyFlags(), w.m_solver.StepJoints());
}

}  // namespace REngine
