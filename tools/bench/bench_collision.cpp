// Narrow-phase cost per pair: REngine's Intersect, Distance (GJK/EPA) and Manifold against
// libccd 2.1 (ccdGJKIntersect, ccdGJKPenetration = GJK+EPA, ccdMPRPenetration) and FCL 0.7
// (collide with contacts, distance), on the same 1000 random pairs of 32-vertex hulls
// (fixed seed, about half overlapping), cycled. One iteration is one pair, so the reported
// time is ns per pair. "/all" runs every pair; "/overlapping" only the overlapping ones,
// where EPA runs; "/separated" the others, where our Distance and FCL's distance run GJK to
// the closest points but libccd's GJK+EPA stops at the boolean answer (so /all compares
// unequal work for it: /overlapping is the fair EPA comparison, FCL's distance the fair
// one for /separated).
//
// Each side gets its cheapest input: ours the two hulls in their body frames and the pair's
// relative pose (as the engine calls it); libccd the hulls' world-space vertices,
// transformed beforehand and outside the timing (its support is a plain loop over them).
// libccd runs twice: with its defaults (CCD_INIT: epa and mpr tolerance 1e-4, as the
// reference figures below were measured) and with the tight tolerances the tests use
// (tests/support/CollisionOracles.h: relative 1e-14 for EPA, whose depth is then accurate
// to ~1e-15 relative on most pairs, like ours).
//
// At the end it prints the ratios (libccd / ours; > 1: ours faster). Reference figures,
// libccd 2.1 on random 32-vertex hulls: ~0.8 us GJK intersection,
// ~4.2 us GJK+EPA, ~0.9 us MPR per pair; target: ours >= 3x faster than libccd's GJK+EPA
// and faster than its boolean GJK.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RCollision.h>
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "support/CollisionOracles.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

struct BenchPair {
  std::unique_ptr<OracleHull> a, b;
  OraclePose X_WA, X_WB;
  RConvexShape sa, sb;
  RRelativePose X_AB;
  CcdPosedHull ca, cb;
  ccd_t tight, defaults;  // libccd configurations (see the file comment)
  RScalar scale = 0;      // sum of the bounding radii, m
  bool overlap = false;   // by the exact SAT reference
};

// 32 points on a sphere of radius 0.5 to 2 m: all of them are hull vertices.
std::vector<RVec3> SpherePoints(std::mt19937_64& rng) {
  std::normal_distribution<RScalar> g;
  std::uniform_real_distribution<RScalar> u(std::log(0.5), std::log(2.0));
  const RScalar r = std::exp(u(rng));
  std::vector<RVec3> p;
  for (int i = 0; i < 32; ++i) p.push_back(r * RVec3(g(rng), g(rng), g(rng)).normalized());
  return p;
}

const std::vector<BenchPair>& AllPairs() {
  static const std::vector<BenchPair> pairs = [] {
    std::vector<BenchPair> out;
    std::mt19937_64 rng(0xBE7C'C011'1DE5);
    std::uniform_real_distribution<RScalar> u(0, 1);
    while (out.size() < 1000) {
      BenchPair p;
      p.a = std::make_unique<OracleHull>(SpherePoints(rng));
      p.b = std::make_unique<OracleHull>(SpherePoints(rng));
      if (p.a->Polyhedron().Vertices().size() != 32 || p.b->Polyhedron().Vertices().size() != 32)
        continue;
      p.X_WA = {RVec3(u(rng), u(rng), u(rng)), RandomRotation(rng)};
      p.X_WB.q_WS = RandomRotation(rng);
      // B along a random direction at g times the reach beyond which the two are surely
      // apart; g in [0.7, 1.3] makes about half of these round hulls overlap.
      const RVec3 dir = RandomRotation(rng) * RVec3::UnitX();
      const RScalar reach =
          SupportExtent(*p.a, p.X_WA.q_WS, dir) + SupportExtent(*p.b, p.X_WB.q_WS, -dir);
      p.X_WB.position_W = p.X_WA.position_W + (0.7 + 0.6 * u(rng)) * reach * dir;

      p.sa = {&p.a->Polyhedron(), 0, p.a->Radius()};
      p.sb = {&p.b->Polyhedron(), 0, p.b->Radius()};
      const RMat3 R_WA = p.X_WA.q_WS.toRotationMatrix();
      p.X_AB.R_AB = R_WA.transpose() * p.X_WB.q_WS.toRotationMatrix();
      p.X_AB.t_AB = R_WA.transpose() * (p.X_WB.position_W - p.X_WA.position_W);
      p.ca = PoseForCcd(*p.a, p.X_WA);
      p.cb = PoseForCcd(*p.b, p.X_WB);
      p.scale = p.a->Radius() + p.b->Radius();
      p.tight = MakeCcdConfig(p.scale);
      p.defaults = p.tight;  // same support and centre functions, CCD_INIT's numbers
      p.defaults.max_iterations = static_cast<unsigned long>(-1);
      p.defaults.epa_tolerance = 1e-4;
      p.defaults.mpr_tolerance = 1e-4;
      p.defaults.dist_tolerance = 1e-6;
      const SatResult sat = SatSeparation(
          p.a->Polyhedron().Transformed(R_WA, p.X_WA.position_W),
          p.b->Polyhedron().Transformed(p.X_WB.q_WS.toRotationMatrix(), p.X_WB.position_W), 0,
          1e-4);
      p.overlap = sat.separation < 0;
      out.push_back(std::move(p));
    }
    return out;
  }();
  return pairs;
}

enum class PairSet { kAll, kOverlapping, kSeparated };
const char* SetName(PairSet set) {
  return set == PairSet::kAll           ? "/all"
         : set == PairSet::kOverlapping ? "/overlapping"
                                        : "/separated";
}

std::vector<const BenchPair*> Subset(PairSet set) {
  std::vector<const BenchPair*> s;
  for (const BenchPair& p : AllPairs())
    if (set == PairSet::kAll || p.overlap == (set == PairSet::kOverlapping)) s.push_back(&p);
  return s;
}

// Runs `query` on the pairs in turn, one pair per iteration.
template <typename Query>
void Cycle(benchmark::State& state, PairSet set, Query query) {
  const std::vector<const BenchPair*> pairs = Subset(set);
  std::size_t i = 0;
  for (auto _ : state) {
    query(*pairs[i]);
    if (++i == pairs.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

void Register(const std::string& name, void (*fn)(benchmark::State&, PairSet)) {
  for (const PairSet set : {PairSet::kAll, PairSet::kOverlapping, PairSet::kSeparated})
    benchmark::RegisterBenchmark((name + SetName(set)).c_str(), [fn, set](benchmark::State& s) {
      fn(s, set);
    })->Unit(benchmark::kNanosecond);
}

void OursIntersect(benchmark::State& state, PairSet ov) {
  Cycle(state, ov, [](const BenchPair& p) {
    benchmark::DoNotOptimize(RCollisionSolver::Intersect(p.sa, p.sb, p.X_AB));
  });
}
void OursDistance(benchmark::State& state, PairSet ov) {
  Cycle(state, ov, [](const BenchPair& p) {
    RDistanceResult r = RCollisionSolver::Distance(p.sa, p.sb, p.X_AB);
    benchmark::DoNotOptimize(r);
  });
}
void OursManifold(benchmark::State& state, PairSet ov) {
  Cycle(state, ov, [](const BenchPair& p) {
    RContactManifold m = RCollisionSolver::Manifold(p.sa, p.sb, p.X_AB, 0);
    benchmark::DoNotOptimize(m);
  });
}

template <bool kTight>
void CcdGjk(benchmark::State& state, PairSet ov) {
  Cycle(state, ov, [](const BenchPair& p) {
    benchmark::DoNotOptimize(ccdGJKIntersect(&p.ca, &p.cb, kTight ? &p.tight : &p.defaults));
  });
}
template <bool kTight>
void CcdEpa(benchmark::State& state, PairSet ov) {
  Cycle(state, ov, [](const BenchPair& p) {
    ccd_real_t depth = 0;
    ccd_vec3_t dir, pos;
    benchmark::DoNotOptimize(
        ccdGJKPenetration(&p.ca, &p.cb, kTight ? &p.tight : &p.defaults, &depth, &dir, &pos));
    benchmark::DoNotOptimize(depth);
  });
}
template <bool kTight>
void CcdMpr(benchmark::State& state, PairSet ov) {
  Cycle(state, ov, [](const BenchPair& p) {
    ccd_real_t depth = 0;
    ccd_vec3_t dir, pos;
    benchmark::DoNotOptimize(
        ccdMPRPenetration(&p.ca, &p.cb, kTight ? &p.tight : &p.defaults, &depth, &dir, &pos));
    benchmark::DoNotOptimize(depth);
  });
}

template <FclSolver kSolver>
void FclCollideBench(benchmark::State& state, PairSet ov) {
  Cycle(state, ov, [](const BenchPair& p) {
    OraclePenetration r = FclCollide(*p.a, p.X_WA, *p.b, p.X_WB, kSolver, 1e-12 * p.scale);
    benchmark::DoNotOptimize(r);
  });
}
template <FclSolver kSolver>
void FclDistanceBench(benchmark::State& state, PairSet ov) {
  Cycle(state, ov, [](const BenchPair& p) {
    OracleDistance r = FclDistance(*p.a, p.X_WA, *p.b, p.X_WB, kSolver, 1e-14 * p.scale);
    benchmark::DoNotOptimize(r);
  });
}

// Console output as usual, plus the mean time per pair of every benchmark, for the ratios:
// the "mean" aggregate when repetitions produce one, else the average of the iterations.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      Mean& m = m_ns[r.run_name.str()];
      // ns: every benchmark here reports in ns.
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name == "mean") {
        m.aggregate = r.GetAdjustedRealTime();
      } else if (r.run_type == Run::RT_Iteration) {
        m.sum += r.GetAdjustedRealTime();
        ++m.count;
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }

  void Finalize() override {
    ConsoleReporter::Finalize();
    auto ratio = [&](const std::string& theirs, const std::string& ours) {
      const auto t = m_ns.find(theirs), o = m_ns.find(ours);
      if (t == m_ns.end() || o == m_ns.end()) return;
      const double nt = t->second.Ns(), no = o->second.Ns();
      if (!(nt > 0 && no > 0)) return;
      std::printf("  %-40s / %-26s = %6.2f   (%8.0f ns / %6.0f ns)\n", theirs.c_str(), ours.c_str(),
                  nt / no, nt, no);
    };
    std::printf("\nratios, libccd or FCL time / ours (> 1: ours faster):\n");
    for (const char* set : {"/all", "/overlapping", "/separated"}) {
      const std::string s = set;
      ratio("libccd/GJK+EPA/defaults" + s, "ours/Distance" + s);
      ratio("libccd/GJK+EPA/tight" + s, "ours/Distance" + s);
      ratio("libccd/GJKIntersect/defaults" + s, "ours/Intersect" + s);
      ratio("libccd/GJKIntersect/tight" + s, "ours/Intersect" + s);
      ratio("libccd/MPR/defaults" + s, "ours/Distance" + s);
      ratio("FCL/collide/GST_INDEP" + s, "ours/Distance" + s);
      ratio("FCL/distance/GST_LIBCCD" + s, "ours/Distance" + s);
    }
    std::printf(
        "target: libccd GJK+EPA / ours Distance >= 3; libccd GJKIntersect / ours "
        "Intersect > 1\n");
  }

 private:
  struct Mean {
    double aggregate = 0, sum = 0;
    int count = 0;
    double Ns() const { return aggregate > 0 ? aggregate : count > 0 ? sum / count : 0; }
  };
  std::map<std::string, Mean> m_ns;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  int overlapping = 0;
  for (const BenchPair& p : AllPairs()) overlapping += p.overlap;
  std::printf("%zu pairs of 32-vertex hulls, %d overlapping (exact SAT reference)\n",
              AllPairs().size(), overlapping);

  Register("ours/Intersect", OursIntersect);
  Register("ours/Distance", OursDistance);
  Register("ours/Manifold", OursManifold);
  Register("libccd/GJKIntersect/defaults", CcdGjk<false>);
  Register("libccd/GJKIntersect/tight", CcdGjk<true>);
  Register("libccd/GJK+EPA/defaults", CcdEpa<false>);
  Register("libccd/GJK+EPA/tight", CcdEpa<true>);
  Register("libccd/MPR/defaults", CcdMpr<false>);
  Register("libccd/MPR/tight", CcdMpr<true>);
  Register("FCL/collide/GST_LIBCCD", FclCollideBench<FclSolver::kLibccd>);
  Register("FCL/collide/GST_INDEP", FclCollideBench<FclSolver::kIndep>);
  Register("FCL/distance/GST_LIBCCD", FclDistanceBench<FclSolver::kLibccd>);
  Register("FCL/distance/GST_INDEP", FclDistanceBench<FclSolver::kIndep>);

  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
