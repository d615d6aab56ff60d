// rengine-bench --characters (characters.h).
#include "characters.h"

#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RCharacter.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RQueries.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>

namespace rbench {

using namespace REngine;

namespace {

constexpr RScalar kDt = 1.0 / 60, kPi = 3.14159265358979323846;

struct World {
  RBodies bodies;
  RIntegrator integrator;
  RQueries queries;
  RVec3 gravity = RVec3(0, -9.81, 0);
  std::vector<RCharacter> characters;
  World() { integrator.Settings().gravity_W = gravity, integrator.Settings().threads = 1; }
  RBodyHandle Box(const RVec3& half, const RVec3& at, RBodyKind kind, RScalar density = 200) {
    RBodyDef d;
    d.shape = RShape::Box(half);
    d.position_W = at;
    d.kind = kind;
    d.density = density;
    return bodies.Add(d);
  }
  void AddCapsule(const RVec3& feet) {
    RCharacterDef def;
    def.shape = RShape::Capsule(0.3, 0.6);
    def.position_W = feet + RVec3(0, 0.901, 0);
    characters.emplace_back(def);
  }
  // One step: the world, then every character; returns the characters' time, s.
  double Step() {
    integrator.Update(bodies, kDt);
    const auto t0 = std::chrono::steady_clock::now();
    for (RCharacter& c : characters) c.Update(bodies, queries, kDt, gravity);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
};

// A scene: builds its world, then runs its updates, calling `measure` after each with the
// world (which accumulates the error); returns the error.
struct Scene {
  const char* name;
  const char* unit;
  std::function<void(World&, int characters)> build;
  std::function<void(World&, int update)> input;
  std::function<double(const World&, int update, std::vector<RVec3>& memory)> error;
};

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

std::vector<Scene> Scenes() {
  std::vector<Scene> s;
  // A 48 x 48 m floor of 1 m tiles; characters in a grid, each walking at 3 m/s in its own
  // direction, turned back towards the middle before the edge. Error: on the level floor,
  // |horizontal speed - 3| and |height - start| (m/s and m; the larger).
  s.push_back({"tiles", "m/s | m",
               [](World& w, int n) {
                 for (int i = 0; i < 48; ++i)
                   for (int j = 0; j < 48; ++j) w.Box(RVec3(0.5, 0.1, 0.5), RVec3(i - 23.5, -0.1, j - 23.5), RBodyKind::kStatic);
                 const int side = int(std::ceil(std::sqrt(double(n))));
                 for (int k = 0; k < n; ++k) w.AddCapsule(RVec3(-10 + 20.0 * (k % side) / side, 0, -10 + 20.0 * (k / side) / side));
               },
               [](World& w, int update) {
                 for (std::size_t k = 0; k < w.characters.size(); ++k) {
                   const RScalar a = 2 * kPi * double(k) / double(w.characters.size()) + (update / 240) * kPi;
                   w.characters[k].SetDesiredVelocity(RVec3(3 * std::cos(a), 0, 3 * std::sin(a)));
                 }
               },
               [](const World& w, int update, std::vector<RVec3>& memory) {
                 double e = 0;
                 if (memory.empty()) {
                   for (const RCharacter& c : w.characters) memory.push_back(c.Position_W());
                   return e;
                 }
                 for (std::size_t k = 0; k < w.characters.size(); ++k) {
                   const RCharacter& c = w.characters[k];
                   if (update > 30 && update % 240 != 0 && c.OnGround()) {
                     const RVec3 v = c.MovedVelocity_W();
                     e = std::max({e, std::abs(std::hypot(v.x(), v.z()) - 3), std::abs(c.Position_W().y() - 0.901)});
                   }
                 }
                 return e;
               }});
  // A 12 m kinematic deck turning at 0.5 rad/s and moving at 1 m/s; the characters stand
  // still on it. Error: how far each has drifted from its place on the deck, m.
  s.push_back({"turning deck", "m",
               [](World& w, int n) {
                 const RBodyHandle deck = w.Box(RVec3(6, 0.1, 6), RVec3(0, -0.1, 0), RBodyKind::kKinematic);
                 w.bodies[deck].SetVelocity_W(RVec3(1, 0, 0));
                 w.bodies[deck].SetAngularVelocity_W(RVec3(0, 0.5, 0));
                 const int side = int(std::ceil(std::sqrt(double(n))));
                 for (int k = 0; k < n; ++k) w.AddCapsule(RVec3(-5 + 10.0 * (k % side) / side, 0, -5 + 10.0 * (k / side) / side));
               },
               [](World&, int) {},
               [](const World& w, int update, std::vector<RVec3>& memory) {
                 const RRigidBody& deck = w.bodies.At(0);
                 double e = 0;
                 for (std::size_t k = 0; k < w.characters.size(); ++k) {
                   const RVec3 local = deck.Orientation_WB().conjugate() * (w.characters[k].Position_W() - deck.Position_W());
                   if (update == 30) memory.push_back(local);
                   if (update > 30) e = std::max(e, (local - memory[k]).norm());
                 }
                 return e;
               }});
  // Stairs: 10 steps of 0.2 m, 0.4 m deep, climbed at 2 m/s for 6 s (onto the landing at
  // 2 m, 10 m long), then standing. Error: final height against the landing's, m.
  s.push_back({"stairs", "m",
               [](World& w, int n) {
                 w.Box(RVec3(20, 0.1, 20), RVec3(0, -0.1, 0), RBodyKind::kStatic);
                 for (int i = 0; i < 10; ++i) w.Box(RVec3(0.2, 0.1 * (i + 1), 10), RVec3(2.2 + 0.4 * i, 0.1 * (i + 1), 0), RBodyKind::kStatic);
                 w.Box(RVec3(5, 1, 10), RVec3(11, 1, 0), RBodyKind::kStatic);  // the landing at 2 m
                 for (int k = 0; k < n; ++k) w.AddCapsule(RVec3(0, 0, -8 + 16.0 * k / std::max(1, n)));
               },
               [](World& w, int update) {
                 for (RCharacter& c : w.characters) c.SetDesiredVelocity(RVec3(update < 360 ? 2 : 0, 0, 0));
               },
               [](const World& w, int update, std::vector<RVec3>&) {
                 double e = 0;  // standing on the landing from update 360 (5 s up: 10 m)
                 if (update < 360) return e;
                 for (const RCharacter& c : w.characters) e = std::max(e, std::abs(c.Position_W().y() - (2 + 0.901)));
                 return e;
               }});
  // Crates: 64 crates of 25 kg on the floor, characters walking through them pushing them
  // about. Time only.
  s.push_back({"pushing crates", "-",
               [](World& w, int n) {
                 w.Box(RVec3(30, 0.1, 30), RVec3(0, -0.1, 0), RBodyKind::kStatic);
                 for (int i = 0; i < 8; ++i)
                   for (int j = 0; j < 8; ++j) w.Box(RVec3(0.25, 0.25, 0.25), RVec3(-7 + 2.0 * i, 0.25, -7 + 2.0 * j), RBodyKind::kDynamic);
                 for (int k = 0; k < n; ++k) w.AddCapsule(RVec3(-12, 0, -8 + 16.0 * k / std::max(1, n)));
               },
               [](World& w, int update) {
                 for (RCharacter& c : w.characters) c.SetDesiredVelocity(RVec3(update < 300 ? 2.5 : -2.5, 0, 0.3));
               },
               [](const World&, int, std::vector<RVec3>&) { return 0.0; }});
  return s;
}

}  // namespace

std::vector<CharacterRow> RunCharacters(bool quick, int repeats) {
  std::vector<CharacterRow> rows;
  const std::vector<int> counts = quick ? std::vector<int>{4} : std::vector<int>{1, 16, 128};
  const int updates = quick ? 60 : 600;
  for (const Scene& scene : Scenes()) {
    for (int n : counts) {
      CharacterRow row;
      row.scene = scene.name, row.characters = n, row.updates = updates, row.unit = scene.unit;
      std::vector<double> times;
      for (int r = 0; r < std::max(1, repeats); ++r) {
        World w;
        scene.build(w, n);
        std::vector<RVec3> memory;
        double seconds = 0, error = 0;
        for (int u = 0; u < updates; ++u) {
          scene.input(w, u);
          seconds += w.Step();
          error = std::max(error, scene.error(w, u, memory));
        }
        times.push_back(seconds * 1e6 / (double(n) * updates));
        row.error = error;  // every repeat computes the same bits
      }
      row.microseconds = Median(times);
      rows.push_back(row);
    }
  }
  return rows;
}

void PrintCharacterTable(const std::vector<CharacterRow>& rows) {
  std::printf("%-16s %10s %8s %14s %12s  %s\n", "scene", "characters", "updates", "us/update", "error", "unit");
  for (const CharacterRow& r : rows) {
    std::printf("%-16s %10d %8d %14.2f %12.3g  %s\n", r.scene.c_str(), r.characters, r.updates, r.microseconds,
                r.error, r.unit.c_str());
  }
}

bool WriteCharacterCsv(const std::string& path, const std::vector<CharacterRow>& rows) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f, "scene,characters,updates,us_per_update,error,unit\n");
  for (const CharacterRow& r : rows) {
    std::fprintf(f, "%s,%d,%d,%.6g,%.6g,%s\n", r.scene.c_str(), r.characters, r.updates, r.microseconds, r.error,
                 r.unit.c_str());
  }
  return std::fclose(f) == 0;
}

}  // namespace rbench
