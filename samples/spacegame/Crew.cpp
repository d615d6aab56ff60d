#include "Crew.h"

#include <REngineMath/RQuaternion.h>

namespace spacegame {
using namespace REngine;

namespace {

RCharacterDef CrewDef(const SpaceWorld& world) {
  RCharacterDef def;
  def.name = "crew";
  def.shape = RShape::Capsule(0.3, 0.6);
  // The ring's inner floor on +x is at R - 2.5 from the axis; the capsule stands along -x
  // (up, towards the axis) a centimetre above it.
  const double floor = GameShapes::kStationRingRadius - 2.5;
  def.position_W = world.Config().origin_W + RVec3(floor - 0.91, 2.5, 0);
  def.q_WS = QuatAxisAngle(RVec3::UnitZ(), 0.5 * kPi);  // the capsule's y onto -x
  def.mass = 80;
  def.category = category::kCrew;
  def.mask = category::kStation;  // walks the station; ships and rocks are outside
  return def;
}

}  // namespace

Crew::Crew(SpaceWorld& world) : m_world(world), m_character(CrewDef(world)) {}

RVec3 Crew::SpinGravity_W(const RVec3& p_W) const {
  const RRigidBody& station = m_world.Bodies()[m_world.Station()];
  const RVec3 w = station.AngularVelocity_W();
  const RVec3 r = p_W - station.Position_W();
  // -w x (w x r) = w^2 r_perp: outwards from the axis.
  return -w.cross(w.cross(r));
}

void Crew::Step(double walk) {
  const RRigidBody& station = m_world.Bodies()[m_world.Station()];
  const RVec3 g = SpinGravity_W(m_character.Position_W());
  // Round the ring, the way its surface moves: w x r, across the plane of up.
  const RVec3 along = station.AngularVelocity_W().cross(m_character.Position_W() - station.Position_W());
  const double n = along.norm();
  m_character.SetDesiredVelocity(n > 0 ? RVec3(along * (walk / n)) : RVec3::Zero());
  m_character.Update(m_world.Bodies(), m_world.Queries(), m_world.StepDt(), g);
}

RVec3 Crew::InStation() const {
  const RRigidBody& station = m_world.Bodies()[m_world.Station()];
  return station.ShapeOrientation_WS().conjugate() * (m_character.Position_W() - station.ShapePosition_W());
}

}  // namespace spacegame
