// rengine-sim --events FILE (see events.h).
#include "events.h"

#include "csv.h"

#include <algorithm>

namespace REngine::sim {

EventWriter::EventWriter(std::FILE* out) : m_out(out) {
  m_buffer = "step,time,event,body_a,body_b,x,y,z,nx,ny,nz,normal_impulse,tangent_impulse\n";
}

const EventWriter::Known& EventWriter::Body(RBodyHandle h, const RBodies& bodies) {
  const std::uint64_t key = (std::uint64_t(h.index) << 32) | h.generation;
  const auto it = m_known.find(key);
  if (it != m_known.end()) return it->second;
  // First named: the body is alive (an event names a removed body only after one named it
  // alive, when its pair began).
  Known k;
  if (const RRigidBody* b = bodies.Find(h)) k.id = b->Id().value_or(0), k.name = CsvField(b->Name());
  return m_known.emplace(key, std::move(k)).first->second;
}

void EventWriter::Know(const RBodies& bodies) {
  for (std::size_t d = 0; d < bodies.Size(); ++d) Body(bodies.HandleAt(d), bodies);
}

void EventWriter::Write(std::uint64_t step, double dt, const std::vector<RContactEvent>& events,
                        const RBodies& bodies) {
  m_rows.clear();
  for (std::size_t e = 0; e < events.size(); ++e) {
    const RContactEvent& ev = events[e];
    if (ev.type == RContactEventType::kPersist) continue;
    const std::uint32_t idA = Body(ev.handleA, bodies).id, idB = Body(ev.handleB, bodies).id;
    const bool swapped = idB < idA;
    m_rows.push_back({swapped ? idB : idA, swapped ? idA : idB, ev.type, swapped, e});
  }
  std::sort(m_rows.begin(), m_rows.end(), [](const Row& x, const Row& y) {
    return x.idA != y.idA ? x.idA < y.idA : x.idB != y.idB ? x.idB < y.idB : x.type < y.type;
  });
  const std::string stepText = std::to_string(step);
  // A product, not a running sum, so that time carries no accumulated rounding.
  const double time = static_cast<double>(step) * dt;
  for (const Row& r : m_rows) {
    const RContactEvent& ev = events[r.event];
    const RVec3 normal_W = r.swapped ? RVec3(-ev.normal_W) : ev.normal_W;
    m_buffer += stepText;
    AppendNumber(m_buffer, time);
    m_buffer += ',';
    m_buffer += ToString(r.type);
    m_buffer += ',';
    m_buffer += Body(r.swapped ? ev.handleB : ev.handleA, bodies).name;
    m_buffer += ',';
    m_buffer += Body(r.swapped ? ev.handleA : ev.handleB, bodies).name;
    for (int a = 0; a < 3; ++a) AppendNumber(m_buffer, ev.point_W[a]);
    for (int a = 0; a < 3; ++a) AppendNumber(m_buffer, normal_W[a]);
    AppendNumber(m_buffer, ev.normalImpulse);
    AppendNumber(m_buffer, ev.frictionImpulse);
    m_buffer += '\n';
  }
  if (m_buffer.size() >= (std::size_t(1) << 20)) Flush();
}

void EventWriter::WriteCharacters(std::uint64_t step, double dt, const std::vector<RCharacter>& characters,
                                  const RBodies& bodies) {
  m_touching.resize(characters.size());
  const std::string stepText = std::to_string(step);
  const double time = static_cast<double>(step) * dt;
  const auto row = [&](const char* type, const RCharacter& c, const RCharacterContact& k) {
    m_buffer += stepText;
    AppendNumber(m_buffer, time);
    m_buffer += ',';
    m_buffer += type;
    m_buffer += ',';
    m_buffer += CsvField(c.Name());
    m_buffer += ',';
    m_buffer += Body(k.body, bodies).name;
    for (int a = 0; a < 3; ++a) AppendNumber(m_buffer, k.point_W[a]);
    for (int a = 0; a < 3; ++a) AppendNumber(m_buffer, -k.normal_W[a]);
    AppendNumber(m_buffer, 0.0);
    AppendNumber(m_buffer, 0.0);
    m_buffer += '\n';
  };
  for (std::size_t i = 0; i < characters.size(); ++i) {
    const std::vector<RCharacterContact>& now = characters[i].Contacts();
    std::vector<RCharacterContact>& before = m_touching[i];
    // Both in handle order (RCharacter::Contacts): a merge.
    std::size_t a = 0, b = 0;
    while (a < before.size() || b < now.size()) {
      if (b == now.size() || (a < before.size() && before[a].body < now[b].body)) {
        row("end", characters[i], before[a++]);
      } else if (a == before.size() || now[b].body < before[a].body) {
        row("begin", characters[i], now[b++]);
      } else {
        ++a, ++b;
      }
    }
    before = now;
  }
  if (m_buffer.size() >= (std::size_t(1) << 20)) Flush();
}

bool EventWriter::Flush() {
  if (std::fwrite(m_buffer.data(), 1, m_buffer.size(), m_out) != m_buffer.size()) m_failed = true;
  m_buffer.clear();
  return !m_failed && std::fflush(m_out) == 0;
}

}  // namespace REngine::sim
