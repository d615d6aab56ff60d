// The characters' record of a world state (RStateCharacters.h).
#include "state/RStateCharacters.h"

#include <REnginePhysics/RWorldState.h>

namespace REngine::state {

namespace {

void WriteContact(RWriter& w, const RCharacterContact& k) {
  w.U32(k.body.index), w.U32(k.body.generation);
  w.Vec3(k.point_W), w.Vec3(k.normal_W), w.F64(k.distance), w.Vec3(k.surfaceVelocity_W);
}

RCharacterContact ReadContact(RReader& r) {
  RCharacterContact k;
  k.body.index = r.U32("contact.body");
  k.body.generation = r.U32("contact.body");
  k.point_W = r.FiniteVec3("contact.point");
  k.normal_W = r.FiniteVec3("contact.normal");
  k.distance = r.Finite("contact.distance");
  k.surfaceVelocity_W = r.FiniteVec3("contact.surface_velocity");
  return k;
}

}  // namespace

void WriteCharacters(RWriter& w, const std::vector<RCharacter>* characters) {
  w.U64(characters ? characters->size() : 0);
  if (!characters) return;
  for (const RCharacter& c : *characters) {
    const RCharacter::RState s = c.State();
    w.String(c.Name());
    w.Vec3(s.position), w.Quat(s.q);
    w.Vec3(s.velocity), w.Vec3(s.desired), w.Vec3(s.moved), w.Vec3(s.up);
    w.F64(s.jump), w.Vec3(s.airCarry);
    w.U8(static_cast<std::uint8_t>(s.ground.state));
    WriteContact(w, s.ground.contact);
    w.Vec3(s.ground.surfaceNormal_W);
    w.Vec3(s.groundLocal), w.Quat(s.groundQ);
    w.U64(s.updates);
    w.U64(s.contacts.size());
    for (const RCharacterContact& k : s.contacts) WriteContact(w, k);
  }
}

std::vector<RCharacter> ReadCharacters(RReader& r, const std::vector<RCharacter>* target) {
  r.SetRecord("characters");
  const std::size_t count = r.Count("count", 8);
  const std::size_t have = target ? target->size() : 0;
  if (count != have) {
    r.Fail("count", "the state holds " + std::to_string(count) + " characters, the loading world (RLoadOptions::"
                    "characters) " + std::to_string(have));
  }
  std::vector<RCharacter> out;
  if (!target) return out;
  out = *target;
  for (std::size_t i = 0; i < count; ++i) {
    r.SetRecord("characters[" + std::to_string(i) + "]");
    const std::string name = r.String("name");
    if (name != out[i].Name()) {
      r.Fail("name", "is \"" + name + "\"; the loading world's character there is \"" + out[i].Name() + "\"");
    }
    RCharacter::RState s;
    s.position = r.Vec3("position");
    s.q = r.Quat("orientation");
    s.velocity = r.Vec3("velocity"), s.desired = r.Vec3("desired"), s.moved = r.Vec3("moved");
    s.up = r.Vec3("up");
    s.jump = r.F64("jump");
    s.airCarry = r.Vec3("air_carry");
    const std::uint8_t ground = r.U8("ground.state");
    if (ground > 2) r.Fail("ground.state", "must be 0, 1 or 2");
    s.ground.state = static_cast<RGroundState>(ground);
    s.ground.contact = ReadContact(r);
    s.ground.surfaceNormal_W = r.FiniteVec3("ground.surface_normal");
    s.groundLocal = r.Vec3("ground_local");
    s.groundQ = r.Quat("ground_orientation");
    s.updates = r.U64("updates");
    s.contacts.resize(r.Count("contacts", 4 * 8 + 8 * 13));
    for (RCharacterContact& k : s.contacts) k = ReadContact(r);
    try {
      out[i].Restore(s);
    } catch (const RCharacterError& e) {
      r.Fail(e.Field(), e.Problem());
    }
  }
  return out;
}

}  // namespace REngine::state
