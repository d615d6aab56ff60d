#include "Session.h"

#include <algorithm>
#include <stdexcept>

namespace rollback {

void Link::Send(std::uint64_t tick, std::uint64_t frame, const Input& input) {
  std::uint64_t z = (m_state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  const std::uint64_t late = m_settings.jitter > 0 ? z % static_cast<std::uint64_t>(m_settings.jitter + 1) : 0;
  m_inFlight.push_back({tick + static_cast<std::uint64_t>(m_settings.delay) + late, tick, frame, input});
}

template <class F>
void Link::Deliver(std::uint64_t tick, F&& onMessage) {
  // By arrival, then by sending order: a message overtaken by a later one arrives after it.
  std::stable_sort(m_inFlight.begin(), m_inFlight.end(),
                   [](const Message& a, const Message& b) { return a.arrival < b.arrival; });
  std::size_t k = 0;
  for (; k < m_inFlight.size() && m_inFlight[k].arrival <= tick; ++k) onMessage(m_inFlight[k].frame, m_inFlight[k].input);
  m_inFlight.erase(m_inFlight.begin(), m_inFlight.begin() + static_cast<std::ptrdiff_t>(k));
}

Peer::Peer(int local, std::size_t maxPrediction, int threads)
    : arena(threads), m_local(local), m_maxPrediction(maxPrediction), m_ring(maxPrediction + 2) {
  m_hashes.push_back(arena.Hash());
  m_ring.Save(arena.integrator, arena.bodies);  // frame 0
}

void Peer::OnRemote(std::uint64_t frame, const Input& input) {
  if (m_remote.size() <= frame) m_remote.resize(frame + 1);
  m_remote[frame] = input;
  while (m_remoteConfirmed + 1 < m_remote.size() && m_remote[m_remoteConfirmed + 1]) ++m_remoteConfirmed;
  if (frame <= Frame() && m_usedRemote[frame] != input) {
    m_rollbackTo = m_rollbackTo ? std::min(*m_rollbackTo, frame) : frame;
  }
}

FrameInputs Peer::InputsFor(std::uint64_t frame) {
  Input remote;  // nothing received yet: no buttons
  for (std::uint64_t k = std::min<std::uint64_t>(frame, m_remote.size() - 1); k > 0; --k) {
    if (m_remote[k]) {
      remote = *m_remote[k];  // the real one, or the last one received before it, repeated
      break;
    }
  }
  if (m_usedRemote.size() <= frame) m_usedRemote.resize(frame + 1);
  m_usedRemote[frame] = remote;
  FrameInputs inputs;
  inputs[m_local] = m_localInputs[frame];
  inputs[1 - m_local] = remote;
  return inputs;
}

void Peer::Simulate(std::uint64_t frame) {
  arena.Advance(InputsFor(frame));
  if (m_hashes.size() <= frame) m_hashes.resize(frame + 1);
  m_hashes[frame] = arena.Hash();
  m_ring.Save(arena.integrator, arena.bodies);
}

void Peer::Reconcile() {
  if (!m_rollbackTo) return;
  const std::uint64_t from = *m_rollbackTo, now = Frame();
  m_rollbackTo.reset();
  m_ring.Restore(arena.integrator, arena.bodies, from - 1);
  for (std::uint64_t f = from; f <= now; ++f) Simulate(f);
  ++rollbacks;
  resimulated += now - from + 1;
  deepest = std::max<std::size_t>(deepest, now - from + 1);
}

bool Peer::CanAdvance(std::uint64_t lastFrame) const {
  return Frame() < lastFrame && Frame() < m_remoteConfirmed + m_maxPrediction;
}

void Peer::Advance(const Input& local) {
  const std::uint64_t frame = Frame() + 1;
  m_localInputs.push_back(local);
  Simulate(frame);
}

std::uint64_t Peer::Confirmed() const {
  return m_rollbackTo ? std::min(Frame(), *m_rollbackTo - 1) : std::min(Frame(), m_remoteConfirmed);
}

SessionResult PlaySession(std::uint64_t frames, const LinkSettings& link, std::size_t maxPrediction, int threadsB) {
  SessionResult result;
  result.frames = frames;
  Player players[kPlayers] = {Player(link.seed * 7919 + 1), Player(link.seed * 7919 + 2)};
  std::vector<FrameInputs> truth(frames + 1);
  Peer peers[kPlayers] = {Peer(0, maxPrediction, 1), Peer(1, maxPrediction, threadsB)};
  LinkSettings back = link;
  back.seed = link.seed ^ 0x5bd1e995u;
  Link links[kPlayers] = {Link(link), Link(back)};  // links[p]: from peer p to the other
  std::uint64_t tick = 0;
  for (; peers[0].Confirmed() < frames || peers[1].Confirmed() < frames; ++tick) {
    if (tick > 100 * frames + 1000) throw std::logic_error("rollback session: the peers stopped confirming frames");
    for (int p = 0; p < kPlayers; ++p) {
      links[1 - p].Deliver(tick, [&](std::uint64_t f, const Input& in) { peers[p].OnRemote(f, in); });
      peers[p].Reconcile();
    }
    for (int p = 0; p < kPlayers; ++p) {
      if (!peers[p].CanAdvance(frames)) {
        peers[p].stalls += peers[p].Frame() < frames;
        continue;
      }
      const Input local = players[p].Next();
      truth[peers[p].Frame() + 1][p] = local;
      peers[p].Advance(local);
      links[p].Send(tick, peers[p].Frame(), local);
    }
  }
  result.ticks = tick;
  Arena reference;
  for (std::uint64_t f = 1; f <= frames; ++f) {
    reference.Advance(truth[f]);
    result.reference.push_back(reference.Hash());
    result.peerA.push_back(peers[0].HashAt(f));
    result.peerB.push_back(peers[1].HashAt(f));
    result.mostShots = std::max(result.mostShots, reference.Shots());
    result.mostAsleep = std::max(result.mostAsleep, reference.Sleeping());
    if (!result.firstMismatch && (result.peerA.back() != result.reference.back() ||
                                  result.peerB.back() != result.reference.back())) {
      result.firstMismatch = f;
    }
  }
  for (const Peer& p : peers) {
    result.rollbacks += p.rollbacks, result.resimulated += p.resimulated, result.stalls += p.stalls;
    result.deepest = std::max(result.deepest, p.deepest);
  }
  return result;
}

}  // namespace rollback
