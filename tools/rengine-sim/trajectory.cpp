// rengine-sim's trajectory CSV and final-state hash (see trajectory.h).
#include "trajectory.h"

#include "csv.h"

#include <charconv>
#include <cstring>

namespace REngine::sim {

std::array<RScalar, 13> BodyState(const RRigidBody& b) {
  const RVec3 x = b.ShapePosition_W();
  const RQuat q = b.ShapeOrientation_WS();
  const RVec3& v = b.Velocity_W();
  const RVec3 w = b.AngularVelocity_W();
  return {x.x(), x.y(), x.z(), q.w(), q.x(), q.y(), q.z(),
          v.x(), v.y(), v.z(), w.x(), w.y(), w.z()};
}

std::array<RScalar, 13> CharacterState(const RCharacter& c) {
  const RVec3& x = c.Position_W();
  const RQuat& q = c.Orientation_WS();
  const RVec3& v = c.MovedVelocity_W();
  return {x.x(), x.y(), x.z(), q.w(), q.x(), q.y(), q.z(), v.x(), v.y(), v.z(), 0, 0, 0};
}

std::uint64_t StateHash(const RSceneWorld& world) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  const auto add = [&h](const std::array<RScalar, 13>& state) {
    unsigned char bytes[sizeof state];
    std::memcpy(bytes, state.data(), sizeof state);
    for (unsigned char byte : bytes) h = (h ^ byte) * 0x100000001b3ULL;
  };
  for (RBodyHandle handle : world.Live()) add(BodyState(world.Bodies()[handle]));
  for (const RCharacter& c : world.Characters()) add(CharacterState(c));
  return h;
}

TrajectoryWriter::TrajectoryWriter(std::FILE* out) : m_out(out) {
  m_buffer = "step,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";
  m_buffer.reserve(kChunk + 4096);
}

void TrajectoryWriter::Rows(std::uint64_t step, RScalar dt, const RSceneWorld& world) {
  char stepText[24];
  const auto stepLength =
      static_cast<std::size_t>(std::to_chars(stepText, stepText + sizeof stepText, step).ptr - stepText);
  // A product, not a running sum, so that time carries no accumulated rounding.
  const RScalar time = static_cast<RScalar>(step) * dt;
  for (RBodyHandle h : world.Live()) {
    const RRigidBody& b = world.Bodies()[h];
    m_buffer.append(stepText, stepLength);
    AppendNumber(m_buffer, time);
    m_buffer += ',';
    m_buffer += CsvName(h, b);
    for (RScalar value : BodyState(b)) AppendNumber(m_buffer, value);
    m_buffer += '\n';
    if (m_buffer.size() >= kChunk) Flush();
  }
  const std::vector<RCharacter>& characters = world.Characters();
  if (m_characterNames.size() != characters.size()) {
    m_characterNames.clear();
    for (const RCharacter& c : characters) m_characterNames.push_back(CsvField(c.Name()));
  }
  for (std::size_t i = 0; i < characters.size(); ++i) {
    m_buffer.append(stepText, stepLength);
    AppendNumber(m_buffer, time);
    m_buffer += ',';
    m_buffer += m_characterNames[i];
    for (RScalar value : CharacterState(characters[i])) AppendNumber(m_buffer, value);
    m_buffer += '\n';
  }
  if (m_buffer.size() >= kChunk) Flush();
}

bool TrajectoryWriter::Flush() {
  if (std::fwrite(m_buffer.data(), 1, m_buffer.size(), m_out) != m_buffer.size()) m_failed = true;
  m_buffer.clear();
  return !m_failed && std::fflush(m_out) == 0;
}

const std::string& TrajectoryWriter::CsvName(RBodyHandle h, const RRigidBody& b) {
  if (h.index >= m_names.size()) m_names.resize(h.index + 1);
  Name& n = m_names[h.index];
  if (!n.valid || n.generation != h.generation) n = {true, h.generation, CsvField(b.Name())};
  return n.text;
}

}  // namespace REngine::sim
