// rengine-bench's engines (engines.h): REngine's integrator, and Bullet's world built by
// tools/bench/BulletWorld.h as bench_bullet builds it.
#include "engines.h"

#ifdef RENGINE_HAVE_BULLET
#include "BulletWorld.h"
#endif

#include <cstddef>
#include <memory>
#include <utility>

using namespace REngine;

namespace rbench {

namespace {

class REngineEngine final : public Engine {
  // The grid measures the solver: every body simulated every step, as Bullet's are with its
  // sleeping off. What sleeping and the other shortcuts buy is --shortcuts' subject.
  static World Unslept(World w) {
    w.settings.shortcuts.sleeping = false;
    return w;
  }

 public:
  explicit REngineEngine(World world)
      : Engine(world.dt, world.steps),
        m_world(Unslept(std::move(world))),
        m_integrator(m_world.settings) {}
  void Step(std::uint64_t n) override {
    for (std::uint64_t i = 0; i < n; ++i) m_integrator.Update(m_world.bodies, m_world.dt);
  }
  void Read(State& out) const override {
    out.resize(m_world.bodies.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
      const RRigidBody& b = m_world.bodies[i];
      out[i] = {b.IsStatic(),       b.Mass(),       b.Inertia_B(),        b.Position_W(),
                b.Orientation_WB(), b.Velocity_W(), b.AngularVelocity_W()};
    }
  }

 private:
  World m_world;
  RIntegrator m_integrator;
};

#ifdef RENGINE_HAVE_BULLET
class BulletEngine final : public Engine {
 public:
  // The World keeps REngine's bodies: the Bullet world points to them for mass properties,
  // so they stay here, unmoved, for the engine's life.
  explicit BulletEngine(World world) : Engine(world.dt, world.steps), m_world(std::move(world)) {
    const bench::BulletCoefficients coeffs =
        bench::ChooseCoefficients(m_world.settings, m_world.bodies, /*match=*/true);
    m_bullet = bench::BuildBullet(m_world.settings, m_world.bodies, coeffs, /*sleep=*/false);
    // Gyroscopic term: BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY, the flag Bullet recommends
    // for a free tumbling body (btRigidBody.h: BT_ENABLE_GYROPSCOPIC_FORCE is an alias of it,
    // on by default since 2.83; the explicit variant is unstable at large spins and the
    // implicit world-frame one is the less accurate of the two implicit forms, per Bullet's
    // GyroscopicDemo). Set explicitly so the choice does not depend on the default.
    const int gyro = BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT |
                     BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD |
                     BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY;
    for (auto& b : m_bullet->bodies) {
      if (b->isStaticObject()) continue;
      b->setFlags((b->getFlags() & ~gyro) | BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
    }
  }
  void Step(std::uint64_t n) override {
    const btScalar dt = bench::Bt(m_world.dt);
    for (std::uint64_t i = 0; i < n; ++i) m_bullet->world.stepSimulation(dt, 0);
  }
  void Read(State& out) const override {
    out.resize(m_bullet->bodies.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
      const RRigidBody& ref = *m_bullet->reference[i];
      const btRigidBody& b = *m_bullet->bodies[i];
      const btTransform& X_WB = b.getCenterOfMassTransform();
      out[i] = {ref.IsStatic(),
                ref.Mass(),
                ref.Inertia_B(),
                bench::R(X_WB.getOrigin()),
                bench::R(X_WB.getRotation()),
                ref.IsStatic() ? RVec3(RVec3::Zero()) : bench::R(b.getLinearVelocity()),
                ref.IsStatic() ? RVec3(RVec3::Zero()) : bench::R(b.getAngularVelocity())};
    }
  }

 private:
  World m_world;
  std::unique_ptr<bench::BulletWorld> m_bullet;
};
#endif

}  // namespace

std::unique_ptr<Engine> MakeEngine(Method method, World world) {
#ifdef RENGINE_HAVE_BULLET
  if (method == Method::kBullet) return std::make_unique<BulletEngine>(std::move(world));
#endif
  (void)method;
  return std::make_unique<REngineEngine>(std::move(world));
}

}  // namespace rbench
