// Two peers playing the arena (Arena.h) over a simulated link, GGPO-style: each simulates
// every frame at once with its own input and a prediction of the other's (the last input
// received, repeated), saves the frame (RSnapshotRing), and when the real input of a frame it
// predicted wrongly arrives, restores the frame before it and simulates the frames since
// again. A peer runs at most maxPrediction frames ahead of the inputs it has confirmed (then
// it waits, as GGPO does). Messages are delayed by `delay` ticks plus up to `jitter` more
// (a deterministic PRNG), so they also arrive out of order.
#pragma once

#include "Arena.h"

#include <REnginePhysics/RSnapshot.h>

#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

namespace rollback {

struct LinkSettings {
  int delay = 3;   // ticks (frames) a message takes at least
  int jitter = 4;  // and up to this many more
  std::uint64_t seed = 1;
};

// One direction of the link: each input is sent as its own message.
class Link {
 public:
  explicit Link(const LinkSettings& s) : m_settings(s), m_state(s.seed) {}
  void Send(std::uint64_t tick, std::uint64_t frame, const Input& input);
  // The messages that have arrived by `tick`, in the order they arrive.
  template <class F>
  void Deliver(std::uint64_t tick, F&& onMessage);
  bool Empty() const { return m_inFlight.empty(); }

 private:
  struct Message {
    std::uint64_t arrival, sent, frame;
    Input input;
  };
  LinkSettings m_settings;
  std::uint64_t m_state;
  std::vector<Message> m_inFlight;
};

class Peer {
 public:
  // local: this peer's player; threads: its step's threads.
  Peer(int local, std::size_t maxPrediction, int threads);
  // The other player's real input for a frame.
  void OnRemote(std::uint64_t frame, const Input& input);
  // Rolls back if a prediction was wrong (see the top of the file).
  void Reconcile();
  bool CanAdvance(std::uint64_t lastFrame) const;
  // Simulates the next frame with the local input and the remote one known or predicted.
  void Advance(const Input& local);
  std::uint64_t Frame() const { return arena.integrator.StepCount(); }
  // The last frame whose every input is known and that was simulated with them: its hash is final.
  std::uint64_t Confirmed() const;
  std::uint64_t HashAt(std::uint64_t frame) const { return m_hashes.at(frame); }

  Arena arena;
  std::size_t rollbacks = 0, resimulated = 0, deepest = 0, stalls = 0;

 private:
  FrameInputs InputsFor(std::uint64_t frame);
  void Simulate(std::uint64_t frame);

  int m_local;
  std::size_t m_maxPrediction;
  REngine::RSnapshotRing m_ring;
  std::vector<Input> m_localInputs{Input{}};                 // by frame (1-based)
  std::vector<std::optional<Input>> m_remote{Input{}};       // by frame, as received
  std::vector<Input> m_usedRemote{Input{}};                  // what each frame was simulated with
  std::vector<std::uint64_t> m_hashes;                       // by frame, the last simulation's
  std::uint64_t m_remoteConfirmed = 0;  // every remote input up to this frame is known
  std::optional<std::uint64_t> m_rollbackTo;  // the earliest frame simulated with a wrong guess
};

struct SessionResult {
  std::uint64_t frames = 0, ticks = 0;
  std::vector<std::uint64_t> reference, peerA, peerB;  // hash by frame (index 0: frame 1)
  std::size_t rollbacks = 0, resimulated = 0, deepest = 0, stalls = 0;
  std::size_t mostShots = 0, mostAsleep = 0;
  std::uint64_t firstMismatch = 0;  // 0: every confirmed frame agrees
};

// Plays `frames` frames on both peers and a reference that never rolls back (the true
// inputs, in order), and compares every confirmed frame's hash. threadsB: peer B's threads.
SessionResult PlaySession(std::uint64_t frames, const LinkSettings& link, std::size_t maxPrediction = 8,
                          int threadsB = 1);

}  // namespace rollback
