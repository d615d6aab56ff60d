// Threads (RWorldSettings::threads, RIntegrator::SetJobSystem): the same world stepped on
// 1, 2 and 4 threads, and on a game's job system that runs its tasks backwards, is the same
// world bit for bit after every step: contacts and contact events in the same order, the
// same states. As in Jolt's and Box2D's determinism tests, the comparison is step by step,
// not only at the end.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RJobSystem.h>

#include "support/RandomWorlds.h"
#include "support/Sanitizers.h"
#include "support/TestBodies.h"

#include <gtest/gtest.h>
#include <thread>
#include <stdexcept>
#include <chrono>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <system_error>
#include <vector>

using namespace REngine;
using namespace REngine::test;

namespace {

// A pile falling on a floor beside a zero-g-like crowd of tumbling boxes, spheres and hulls
// flying through each other's paths: contacts, impacts, islands, sleeping.
std::vector<RBodyDef> World(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<RScalar> u(0, 1);
  std::vector<RBodyDef> defs;
  defs.push_back(BoxDef(RVec3(30, 0.5, 30)).At(RVec3(0, -0.5, 0)).Static().Named("floor"));
  for (int i = 0; i < 400; ++i) {
    const RScalar s = 0.2 + 0.5 * u(rng);
    const RScalar aspect = 0.5 + u(rng);
    BodyDef d = i % 3 == 0   ? SphereDef(s)
                : i % 3 == 1 ? BoxDef(RVec3(s, s * aspect, s))
                             : HullDef({RVec3(0, 0, 0), RVec3(s, 0, 0), RVec3(0, s, 0),
                                        RVec3(0, 0, s), RVec3(s, s, s) * 0.6});
    // Draws in a fixed order (DrawVec3): the same world whatever the compiler.
    const RVec3 at = DrawVec3(u, rng);
    d.At(RVec3(12 * at.x() - 6, 0.5 + 10 * at.y(), 12 * at.z() - 6)).Mass(0.5 + 2 * u(rng));
    d.q_WS = DrawQuat(u, rng);
    d.velocity_W = (DrawVec3(u, rng) - RVec3::Constant(0.5)) * 6;
    d.angularVelocity_W = (DrawVec3(u, rng) - RVec3::Constant(0.5)) * 3;
    d.restitution = u(rng);
    d.responds = u(rng) > 0.03;
    defs.push_back(d.Named("b" + std::to_string(i)));
  }
  return defs;
}

bool SameState(const RRigidBody& a, const RRigidBody& b) {
  return a.Position_W() == b.Position_W() && a.Velocity_W() == b.Velocity_W() &&
         a.Orientation_WB().coeffs() == b.Orientation_WB().coeffs() &&
         a.AngularVelocity_B() == b.AngularVelocity_B() && a.IsSleeping() == b.IsSleeping();
}

// A game's job system at its most unhelpful: one thread, tasks run last to first.
class BackwardsJobs final : public RJobSystem {
 public:
  int ThreadCount() const override { return 3; }  // cut the work as for three threads
  void Run(std::size_t count, RTask task, void* context) override {
    for (std::size_t k = count; k-- > 0;) task(context, k), ++tasks;
  }
  std::atomic<std::uint64_t> tasks{0};
};

// Steps `defs` on 1, 2 and 4 threads and on the backwards job system, with churn for the
// first two seconds, comparing every contact and body after every step; returns the
// contacts seen and the most bodies asleep at once.
struct AlikeRun {
  std::uint64_t contacts = 0, sleepers = 0, backwardsTasks = 0;
  std::uint64_t nonFinite = 0;  // bodies put back (NonFiniteInLastStep), over the run
  std::uint64_t events[3] = {0, 0, 0};  // contact events: begin, persist, end
};
AlikeRun StepOnEveryThreadCount(const std::vector<RBodyDef>& defs) {
  AlikeRun run;
  constexpr int kWorlds = 4;
  BackwardsJobs backwards;
  RWorldSettings settings;
  settings.gravity_W = RVec3(0, -9.81, 0);
  // The broad phase's trees every step: by itself the sweep would keep the all-pairs loop
  // for a world this small, and the trees' pair search is one of the stages on threads.
  settings.shortcuts.broadPhaseAlways = true;
  std::vector<RIntegrator> integrators;
  const int threads[kWorlds] = {1, 2, 4, 1};
  for (int k = 0; k < kWorlds; ++k) {
    settings.threads = threads[k];
    integrators.emplace_back(settings);
  }
  integrators[3].SetJobSystem(&backwards);
  std::vector<RBodies> worlds(kWorlds);
  std::vector<std::vector<RBodyHandle>> handles(kWorlds);
  for (int k = 0; k < kWorlds; ++k) {
    for (const RBodyDef& d : defs) handles[k].push_back(worlds[k].Add(d));
  }
  std::mt19937_64 rng(3);
  // Six seconds, and on (to ten at most) until something sleeps: when the pile first comes
  // to rest depends on rounding (the chaos of a pile), and the sleeping path must be stepped.
  for (int s = 0; s < 600 && (s < 360 || run.sleepers == 0); ++s) {
    // Churn: a body removed or added back every few steps, in every world alike (for the
    // first two seconds; then the pile settles and goes to sleep).
    if (s % 9 == 4 && s < 120) {
      const std::size_t i = 1 + rng() % (defs.size() - 1);
      for (int k = 0; k < kWorlds; ++k) {
        if (worlds[k].Contains(handles[k][i])) {
          worlds[k].Remove(handles[k][i]);
        } else {
          handles[k][i] = worlds[k].Add(defs[i]);
        }
      }
    }
    for (int k = 0; k < kWorlds; ++k) integrators[k].Update(worlds[k], 1.0 / 60);
    for (int k = 1; k < kWorlds; ++k) {
      const std::vector<RContact>& c0 = integrators[0].Contacts();
      const std::vector<RContact>& ck = integrators[k].Contacts();
      EXPECT_EQ(c0.size(), ck.size()) << "step " << s << ", world " << k;
      if (c0.size() != ck.size()) return run;
      for (std::size_t c = 0; c < c0.size(); ++c) {
        EXPECT_EQ(c0[c].handleA.index, ck[c].handleA.index) << "step " << s << " contact " << c;
        EXPECT_EQ(c0[c].handleB.index, ck[c].handleB.index) << "step " << s << " contact " << c;
        if (c0[c].handleA.index != ck[c].handleA.index || c0[c].handleB.index != ck[c].handleB.index) return run;
      }
      // Contact events: the same, in the same order, bit for bit.
      const std::vector<RContactEvent>& e0 = integrators[0].Events();
      const std::vector<RContactEvent>& ek = integrators[k].Events();
      EXPECT_EQ(e0.size(), ek.size()) << "step " << s << ", world " << k;
      if (e0.size() != ek.size()) return run;
      for (std::size_t e = 0; e < e0.size(); ++e) {
        const bool same = e0[e].type == ek[e].type && e0[e].handleA == ek[e].handleA &&
                          e0[e].handleB == ek[e].handleB && e0[e].point_W == ek[e].point_W &&
                          e0[e].normal_W == ek[e].normal_W && e0[e].normalImpulse == ek[e].normalImpulse &&
                          e0[e].frictionImpulse == ek[e].frictionImpulse;
        EXPECT_TRUE(same) << "step " << s << ", world " << k << ", event " << e;
        if (!same) return run;
      }
      EXPECT_EQ(worlds[0].Size(), worlds[k].Size());
      if (worlds[0].Size() != worlds[k].Size()) return run;
      for (std::size_t i = 0; i < worlds[0].Size(); ++i) {
        const bool same = SameState(worlds[0].At(i), worlds[k].At(i));
        EXPECT_TRUE(same) << "step " << s << ", world " << k << " (threads " << threads[k] << "), body " << i;
        if (!same) return run;
      }
    }
    run.contacts += integrators[0].Contacts().size();
    for (const RContactEvent& e : integrators[0].Events()) ++run.events[static_cast<int>(e.type)];
    run.nonFinite += integrators[0].NonFiniteInLastStep().size();
    run.sleepers = std::max<std::uint64_t>(run.sleepers, integrators[0].PairStats().sleepingBodies);
  }
  run.backwardsTasks = backwards.tasks.load();
  return run;
}

}  // namespace

TEST(Threads, EveryThreadCountStepsTheSameWorldBitForBit) {
  const AlikeRun run = StepOnEveryThreadCount(World(21));
  EXPECT_GT(run.contacts, 10000u) << "too few contacts to test the solver's order";
  EXPECT_GT(run.sleepers, 0u) << "nothing slept";
  EXPECT_GT(run.backwardsTasks, 0u) << "the game's job system was never used";
  EXPECT_GT(run.events[0], 100u) << "too few begin events";
  EXPECT_GT(run.events[1], 1000u) << "too few persist events";
  EXPECT_GT(run.events[2], 100u) << "too few end events";
}

// The same with kinematic, damped and locked bodies among them: a kinematic paddle sweeping
// the floor, a kinematic platform rising through the crowd, a third of the bodies damped,
// some locked on random axes, some with other gravity scales (falling up, floating,
// heavier).
TEST(Threads, KinematicDampedAndLockedBodiesStepAlikeOnEveryThreadCount) {
  std::vector<RBodyDef> defs = World(22);
  std::mt19937_64 rng(5);
  for (std::size_t i = 1; i < defs.size(); ++i) {
    RBodyDef& d = defs[i];
    if (i % 3 == 0) d.linearDamping = 0.1 * RScalar(rng() % 10), d.angularDamping = 0.2 * RScalar(rng() % 10);
    if (i % 5 == 0) {
      for (int a = 0; a < 3; ++a) d.locks.linear[a] = rng() % 3 == 0, d.locks.angular[a] = rng() % 2 == 0;
    }
    if (i % 7 == 0) d.gravityScale = i % 2 ? -0.3 : 2.0;
    if (i % 11 == 0) d.gravityScale = 0;
  }
  defs.push_back(BoxDef(RVec3(6, 0.3, 0.3)).Kinematic().At(RVec3(0, 0.35, 0))
                     .Spinning(RVec3(0, 1.5, 0)).Named("paddle"));
  defs.push_back(BoxDef(RVec3(2, 0.2, 2)).Kinematic().At(RVec3(3, 0.5, 3))
                     .Moving(RVec3(0, 1, -0.5)).Spinning(RVec3(0, 0.3, 0)).Named("platform"));
  const AlikeRun run = StepOnEveryThreadCount(defs);
  EXPECT_GT(run.contacts, 10000u) << "too few contacts to test the solver's order";
  EXPECT_GT(run.backwardsTasks, 0u);
  EXPECT_EQ(run.nonFinite, 0u) << "a body overflowed and was put back";
}

TEST(Threads, PoolRunsEveryTaskOnceAndReturnsWhenAllAreDone) {
  for (int threads : {1, 2, 3, 8}) {
    RThreadPool pool(threads);
    EXPECT_EQ(pool.ThreadCount(), threads);
    for (std::size_t count : {0u, 1u, 7u, 1000u}) {
      std::vector<std::atomic<int>> runs(count);
      for (auto& r : runs) r = 0;
      pool.Run(count, [](void* p, std::size_t k) {
        (*static_cast<std::vector<std::atomic<int>>*>(p))[k]++;
      }, &runs);
      for (std::size_t k = 0; k < count; ++k) {
        ASSERT_EQ(runs[k].load(), 1) << threads << " threads, task " << k << " of " << count;
      }
    }
  }
}

// Many short stages back to back (a step's pattern: the workers spin between them) and stages
// with slow tasks that outlast the caller's spin (it then sleeps until the last one ends); a
// task that throws: every other task still runs once, Run throws the first exception after
// all have finished, and the pool runs the next stage as before.
TEST(Threads, PoolKeepsCountUnderBurstsSlowTasksAndExceptions) {
  for (int threads : {1, 2, 4}) {
    RThreadPool pool(threads);
    std::vector<std::atomic<int>> runs(64);
    auto count = [](void* p, std::size_t k) { (*static_cast<std::vector<std::atomic<int>>*>(p))[k]++; };
    for (int stage = 0; stage < 20000; ++stage) pool.Run(1 + stage % 64, count, &runs);
    long total = 0;
    for (auto& r : runs) total += r.load();
    long expected = 0;
    for (int stage = 0; stage < 20000; ++stage) expected += 1 + stage % 64;
    EXPECT_EQ(total, expected) << threads << " threads";

    struct Slow {
      std::vector<std::atomic<int>> runs = std::vector<std::atomic<int>>(8);
    } slow;
    pool.Run(8, [](void* p, std::size_t k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(k % 2 ? 3 : 0));
      static_cast<Slow*>(p)->runs[k]++;
    }, &slow);
    for (auto& r : slow.runs) EXPECT_EQ(r.load(), 1) << threads << " threads";

    std::vector<std::atomic<int>> thrown(16);
    for (auto& r : thrown) r = 0;
    try {
      pool.Run(16, [](void* p, std::size_t k) {
        (*static_cast<std::vector<std::atomic<int>>*>(p))[k]++;
        if (k == 3 || k == 11) throw std::runtime_error("task " + std::to_string(k));
      }, &thrown);
      ADD_FAILURE() << "Run did not throw, " << threads << " threads";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_TRUE(what == "task 3" || what == "task 11") << what;
    }
    for (std::size_t k = 0; k < thrown.size(); ++k) EXPECT_EQ(thrown[k].load(), 1) << threads << " threads, task " << k;
    for (auto& r : runs) r = 0;
    pool.Run(64, count, &runs);
    for (auto& r : runs) EXPECT_EQ(r.load(), 1) << threads << " threads, after the exception";
  }
}

TEST(Threads, ParallelRangesCoverEachIndexOnceWhateverTheCut) {
  RThreadPool pool(3);
  for (std::size_t count : {1u, 5u, 64u, 1001u}) {
    for (std::size_t tasks : {1u, 2u, 12u, 5000u}) {
      for (std::size_t grain : {1u, 3u, 100u}) {
        std::vector<int> hits(count, 0);
        std::vector<std::atomic<int>> taskRuns(tasks);
        for (auto& r : taskRuns) r = 0;
        const std::size_t used = ParallelRanges(&pool, count, tasks, grain, [&](std::size_t b, std::size_t e, std::size_t k) {
          for (std::size_t i = b; i < e; ++i) ++hits[i];
          ++taskRuns[k];
          EXPECT_GE(e - b, std::min(grain, count)) << "a range below the grain";
        });
        for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(hits[i], 1) << count << " " << tasks;
        EXPECT_EQ(used, std::min(tasks, std::max<std::size_t>(1, count / grain)));
        for (std::size_t k = 0; k < tasks; ++k) EXPECT_EQ(taskRuns[k].load(), k < used ? 1 : 0);
      }
    }
  }
}

// A thread count out of range is refused before anything moves.
TEST(Threads, AThreadCountOutOfRangeIsRefused) {
  for (int threads : {-1, RWorldSettings::kMaxThreads + 1}) {
    RWorldSettings settings;
    settings.threads = threads;
    RIntegrator integrator(settings);
    std::vector<RRigidBody> bodies;
    bodies.emplace_back(SphereDef(0.5).At(RVec3(0, 0, 0)).Mass(1).Named("a"));
    bodies[0].SetVelocity_W(RVec3(1, 0, 0));
    EXPECT_THROW(integrator.Update(bodies, 1.0 / 60), RError) << threads;
    EXPECT_EQ(bodies[0].Position_W(), RVec3(0, 0, 0)) << "the body moved";
  }
}

// A setting that is not a number, or out of its range, is refused before anything moves,
// naming the setting: a NaN restitution threshold would bounce nothing, a negative slop
// would push resting bodies apart.
TEST(Settings, NonFiniteOrNegativeSettingsAreRefusedNamingTheField) {
  const RScalar nan = std::numeric_limits<RScalar>::quiet_NaN();
  const struct {
    const char* field;
    void (*spoil)(RWorldSettings&, RScalar);
    RScalar bad;
  } cases[] = {
      {"gravity_W", [](RWorldSettings& s, RScalar x) { s.gravity_W.y() = x; }, nan},
      {"restitutionThreshold", [](RWorldSettings& s, RScalar x) { s.restitutionThreshold = x; }, nan},
      {"restitutionThreshold", [](RWorldSettings& s, RScalar x) { s.restitutionThreshold = x; }, -1},
      {"penetrationSlop", [](RWorldSettings& s, RScalar x) { s.penetrationSlop = x; }, -1e-3},
      {"maxPositionCorrection", [](RWorldSettings& s, RScalar x) { s.maxPositionCorrection = x; }, nan},
      {"sleepSpeed", [](RWorldSettings& s, RScalar x) { s.sleepSpeed = x; }, -1},
      {"sleepTime", [](RWorldSettings& s, RScalar x) { s.sleepTime = x; }, std::numeric_limits<RScalar>::infinity()},
      {"positionCorrection", [](RWorldSettings& s, RScalar x) { s.positionCorrection = x; }, -0.5},
      {"positionCorrection", [](RWorldSettings& s, RScalar x) { s.positionCorrection = x; }, nan},
  };
  for (const auto& c : cases) {
    RWorldSettings settings;
    c.spoil(settings, c.bad);
    RIntegrator integrator(settings);
    std::vector<RRigidBody> bodies;
    bodies.emplace_back(SphereDef(0.5).At(RVec3(0, 0, 0)).Mass(1).Named("a"));
    bodies[0].SetVelocity_W(RVec3(1, 0, 0));
    try {
      integrator.Update(bodies, 1.0 / 60);
      ADD_FAILURE() << c.field << " = " << c.bad << " was accepted";
    } catch (const RError& e) {
      EXPECT_EQ(e.Field(), c.field);
    }
    EXPECT_EQ(bodies[0].Position_W(), RVec3(0, 0, 0)) << "the body moved";
  }
}

// A world that is one island of 532 contacts (a block of boxes face to face on a floor): its
// rows are built as tasks before the islands' (FindImpulses), and still the same on every
// thread count.
TEST(Threads, OneLargeIslandStepsAlikeOnEveryThreadCount) {
  std::vector<RBodyDef> defs;
  defs.push_back(BoxDef(RVec3(30, 0.5, 30)).At(RVec3(0, -0.5, 0)).Static().Named("floor"));
  for (int i = 0; i < 7 * 7 * 4; ++i) {
    const int x = i % 7, z = (i / 7) % 7, y = i / 49;
    defs.push_back(BoxDef(RVec3::Constant(0.5)).At(RVec3(x - 3.0, 0.5 + y, z - 3.0)).Mass(1)
                       .Named("c" + std::to_string(i)));
  }
  const AlikeRun run = StepOnEveryThreadCount(defs);
  EXPECT_GT(run.contacts, 500u * 360u) << "the block fell apart: not one large island";
  EXPECT_GT(run.backwardsTasks, 0u);
}

// A pool whose workers cannot all start (here: an address space with room for a few of
// their stacks) stops and joins those that did and throws std::system_error naming the
// thread that failed, instead of destroying its members under running workers (which hung
// in the condition variable's destructor). Run in a child process, so that the limit and a
// hang stay there: a hang is ended by an alarm, a worker left joinable by std::terminate,
// and the child's exit code says which check failed.
TEST(Threads, APoolWhoseThreadsCannotStartThrowsAfterJoiningThoseStarted) {
  if (RENGINE_TEST_SANITIZED) GTEST_SKIP() << "a sanitizer's shadow memory does not run under an address-space limit";
  constexpr int kThreads = 1024;
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    alarm(60);
    // Room for 64 MiB more than the child maps now: far less than 1023 stacks of at least
    // 2 MiB each, far more than the exception's message needs.
    long pages = 0;
    if (std::FILE* statm = std::fopen("/proc/self/statm", "r")) {
      if (std::fscanf(statm, "%ld", &pages) != 1) pages = 0;
      std::fclose(statm);
    }
    if (pages <= 0) _exit(10);
    const rlim_t room = static_cast<rlim_t>(pages) * static_cast<rlim_t>(sysconf(_SC_PAGESIZE)) + (rlim_t(64) << 20);
    rlimit before{};
    if (getrlimit(RLIMIT_AS, &before) != 0) _exit(11);
    const rlimit limit{room, before.rlim_max};  // the soft limit only: it is lifted again below
    if (setrlimit(RLIMIT_AS, &limit) != 0) _exit(11);
    try {
      RThreadPool pool(kThreads);
      _exit(12);  // every thread started: the limit did not bite
    } catch (const std::system_error& e) {
      const std::string what = e.what();
      const std::string prefix = "RThreadPool: could not start thread ";
      if (what.rfind(prefix, 0) != 0) _exit(13);
      const int k = std::atoi(what.c_str() + prefix.size());
      if (k < 2 || k > kThreads) _exit(14);  // the caller's thread is the first: never it
      if (what.find(" of " + std::to_string(kThreads) + ": ") == std::string::npos) _exit(15);
    } catch (...) {
      _exit(16);
    }
    // The limit lifted, a pool starts and runs again in the same process.
    if (setrlimit(RLIMIT_AS, &before) != 0) _exit(17);
    RThreadPool pool(4);
    std::atomic<int> ran{0};
    pool.Run(100, [](void* c, std::size_t) { ++*static_cast<std::atomic<int>*>(c); }, &ran);
    _exit(ran == 100 ? 0 : 18);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child was ended by signal " << WTERMSIG(status)
                                 << (WTERMSIG(status) == SIGALRM ? " (SIGALRM: it hung)" : "");
  EXPECT_EQ(WEXITSTATUS(status), 0) << "see the _exit codes in the child";
}
