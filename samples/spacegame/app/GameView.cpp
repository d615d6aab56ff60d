#include "GameView.h"

#include <REnginePhysics/RJoint.h>

#include <algorithm>

namespace spacegame {
using namespace REngine;

namespace {

Eigen::Vector3f Colour(float r, float g, float b) { return {r, g, b}; }

// What a body looks like: by role, rocks in a few shades by handle so the field is not one
// colour.
Eigen::Vector3f BodyColour(const RRigidBody& b, RBodyHandle h) {
  switch (RoleOf(b)) {
    case Role::kShip:
      return Colour(0.75f, 0.80f, 0.88f);
    case Role::kStation:
      return Colour(0.50f, 0.54f, 0.60f);
    case Role::kBay:
      return Colour(0.38f, 0.40f, 0.44f);
    case Role::kCrate:
      return Colour(0.90f, 0.55f, 0.15f);
    case Role::kMissile:
      return Colour(0.95f, 0.25f, 0.20f);
    case Role::kDebris:
      return Colour(0.95f, 0.80f, 0.35f);
    case Role::kAsteroid: {
      static const Eigen::Vector3f shades[4] = {
          Colour(0.55f, 0.47f, 0.40f), Colour(0.47f, 0.44f, 0.42f), Colour(0.60f, 0.52f, 0.42f),
          Colour(0.42f, 0.38f, 0.36f)};
      return shades[h.index % 4];
    }
    default:
      return Colour(0.7f, 0.7f, 0.7f);
  }
}

}  // namespace

void GameView::Build(const Game& game, const DebugDraw& debug, DrawList& out) {
  out.Clear();
  const SpaceWorld& world = game.World();
  const RBodies& bodies = world.Bodies();
  for (std::size_t i = 0; i < bodies.EnabledCount(); ++i) {
    const RRigidBody& b = bodies.At(i);
    DrawItem item;
    item.shape = b.PreparedShape().get();
    game.DrawPose(i, item.position_W, item.q_WS);
    item.colour = BodyColour(b, bodies.HandleAt(i));
    if (debug.sleeping && b.IsSleeping())
      item.colour = 0.45f * item.colour + Eigen::Vector3f(0.10f, 0.22f, 0.55f);
    out.items.push_back(item);
  }

  // The crew member inside the ring, bright so that it shows against the hull.
  {
    const REngine::RCharacter& crew = game.CrewMember().Character();
    DrawItem item;
    item.shape = &crew.Shape();
    item.position_W = crew.Position_W();
    item.q_WS = crew.Orientation_WS();
    item.colour = Eigen::Vector3f(1.0f, 0.55f, 0.1f);
    out.items.push_back(item);
  }

  // Explosion flashes: a hot ball that grows and fades over 0.6 s of game time (counted in
  // steps, so a paused game holds its flashes). Explosions are the last step's: those of
  // earlier steps of the same frame are not seen.
  const std::uint64_t step = world.Integrator().StepCount();
  if (step != m_lastStep) {
    const double elapsed = double(step - std::min(step, m_lastStep)) * world.StepDt();
    for (Flash& f : m_flashes) f.age += elapsed;
    for (const Explosion& x : game.MissileSystem().LastExplosions())
      m_flashes.push_back({x.point_W, 0});
    m_lastStep = step;
  }
  m_flashes.erase(std::remove_if(m_flashes.begin(), m_flashes.end(),
                                 [](const Flash& f) { return f.age > 0.6; }),
                  m_flashes.end());
  for (const Flash& f : m_flashes) {
    const float t = float(f.age / 0.6);
    DrawItem ball;
    ball.position_W = f.point_W;
    ball.scale = 3.0f + 9.0f * t;
    ball.colour = Colour(1.0f, 0.85f - 0.5f * t, 0.4f - 0.3f * t);
    ball.emissive = 1;
    out.items.push_back(ball);
  }

  if (game.LaserOn()) {
    const Lasers& l = game.LaserSystem();
    out.Line(l.BeamFrom(), l.BeamTo(), Colour(0.3f, 1.0f, 0.4f));
  }
  if (debug.contacts) {
    for (const RContact& c : world.Integrator().Contacts()) {
      for (int k = 0; k < c.manifold.pointCount; ++k) {
        const RVec3 p = c.manifold.points[k].position;
        out.Line(p, p + 1.5 * c.manifold.normal, Colour(1.0f, 0.2f, 0.9f));
        out.Box(p - RVec3::Constant(0.1), p + RVec3::Constant(0.1), Colour(1.0f, 1.0f, 0.2f));
      }
    }
  }
  if (debug.bounds) {
    const std::uint64_t stamp = world.Integrator().CacheStamp();
    for (const RRigidBody& b : bodies) {
      const RWorldForm& f = b.WorldForm(stamp);
      out.Box(f.aabbMin_W, f.aabbMax_W,
              b.IsSleeping() ? Colour(0.3f, 0.5f, 1.0f) : Colour(0.3f, 0.8f, 0.3f));
    }
  }
  if (debug.joints) {
    for (std::size_t j = 0; j < bodies.JointCount(); ++j) {
      const RJoint& joint = bodies.JointAt(j);
      const RRigidBody& a = bodies[joint.def.a];
      const RVec3 anchor = a.Position_W() + a.Orientation_WB() * joint.anchorA_B;
      const RVec3 other = joint.def.b.IsValid() ? bodies[joint.def.b].Position_W() : anchor;
      const Eigen::Vector3f cyan = Colour(0.2f, 0.9f, 1.0f);
      out.Line(a.Position_W(), anchor, cyan);
      out.Line(anchor, other, cyan);
      out.Box(anchor - RVec3::Constant(0.3), anchor + RVec3::Constant(0.3), cyan);
    }
  }
}

void GameView::Aim(Camera& camera, CameraMode mode, const Game& game) {
  if (mode == CameraMode::kCrew) {
    // Inside the ring, behind and above the crew member, its up as the camera's: the floor
    // below, the ring curving up ahead.
    const REngine::RCharacter& crew = game.CrewMember().Character();
    const RVec3 up = crew.Up_W();
    const RVec3 walk = crew.DesiredVelocity_W().norm() > 0 ? RVec3(crew.DesiredVelocity_W().normalized())
                                                           : RVec3(up.unitOrthogonal());
    camera.LookAt(crew.Position_W() - 7.0 * walk + 2.5 * up, crew.Position_W() + 6.0 * walk, up);
    return;
  }
  const RBodies& bodies = game.World().Bodies();
  RVec3 ship = RVec3::Zero();
  RQuat q = RQuat::Identity();
  for (std::size_t i = 0; i < bodies.EnabledCount(); ++i)
    if (bodies.HandleAt(i) == game.World().Ship()) game.DrawPose(i, ship, q);
  if (mode == CameraMode::kChase) {
    const RVec3 up = q * RVec3::UnitY(), fwd = q * RVec3::UnitZ();
    camera.LookAt(ship - 32.0 * fwd + 11.0 * up + 6.0 * (q * RVec3::UnitX()), ship + 40.0 * fwd,
                  up);
    return;
  }
  // The eye comes in as the ship does, so the ship never shrinks to a dot.
  const RVec3 O = game.World().Config().origin_W;
  const double reach = std::clamp((ship - O).norm() / 100, 0.8, 1.6);
  camera.LookAt(O + reach * RVec3(-60, 55, -95), 0.5 * (O + ship), RVec3::UnitY());
}

}  // namespace spacegame
