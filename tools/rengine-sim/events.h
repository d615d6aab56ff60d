// rengine-sim --events FILE: the contact events of every step (docs/scene-format.md,
// "Events CSV") into the CSV
// step,time,event,body_a,body_b,x,y,z,nx,ny,nz,normal_impulse,tangent_impulse.
#pragma once

#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RCharacter.h>
#include <REnginePhysics/RContactEvents.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <vector>

namespace REngine::sim {

class EventWriter {
 public:
  // Writes the header at once; `out` stays the caller's to close.
  explicit EventWriter(std::FILE* out);
  // The begin and end rows of step `step` (RIntegrator::Events after its Update, before
  // that step's actions; persist events are not rows of the format). `time` is step * dt,
  // the end of the step, as the trajectory's row of that step. body_a is the body created
  // first (the scene's order, then the order of `add` actions: RRigidBody::Id), the normal
  // points from it to body_b, and rows are sorted by body_a, body_b, begin before end.
  void Write(std::uint64_t step, double dt, const std::vector<RContactEvent>& events, const RBodies& bodies);
  // The begin and end rows of the characters' contacts in step `step` (after its Update and
  // their Updates): body_a is the character, body_b the body, the normal points from the
  // character to the body, the impulses are 0 (a character is moved, not solved). Rows
  // follow the bodies' rows of the step, by character, then by body.
  void WriteCharacters(std::uint64_t step, double dt, const std::vector<RCharacter>& characters,
                       const RBodies& bodies);
  // Learns the names of every body in the container now: a run loaded from a state
  // (--load-state) may end a pair that began before it, of a body removed since.
  void Know(const RBodies& bodies);
  // Writes what is buffered; false when any write failed.
  bool Flush();

 private:
  // A body as the rows name it: creation order and CSV name, kept by (slot, generation)
  // from the first event that names it, so that an end after its removal still can.
  struct Known {
    std::uint32_t id = 0;  // a scene's bodies all have ids (their index)
    std::string name;
  };
  const Known& Body(RBodyHandle h, const RBodies& bodies);
  struct Row {
    std::uint32_t idA, idB;
    RContactEventType type;
    bool swapped;  // body_a is the event's B
    std::size_t event;
  };

  std::FILE* m_out;
  std::unordered_map<std::uint64_t, Known> m_known;
  std::vector<Row> m_rows;
  // Per character, the bodies it touched after the last step (handle order) with the
  // contact each had.
  std::vector<std::vector<RCharacterContact>> m_touching;
  std::string m_buffer;
  bool m_failed = false;
};

}  // namespace REngine::sim
