// Rollback netcode end to end (samples/rollback): two peers exchange inputs over a link with
// delay and jitter, predict the other's input by repeating the last one, and roll back and
// simulate again when a late input proves them wrong. The independent answer is a run that
// never rolls back, playing the true inputs in order: after every confirmed frame both
// peers' world hashes must equal its hash, bit for bit, with shots spawned and removed by
// the inputs, a pile asleep and woken, and a peer on another thread count.
#include "Session.h"

#include <gtest/gtest.h>

namespace {

void ExpectPeersAgree(const rollback::LinkSettings& link, std::uint64_t frames, int threadsB) {
  const rollback::SessionResult r = rollback::PlaySession(frames, link, 8, threadsB);
  ASSERT_EQ(r.reference.size(), frames);
  for (std::uint64_t f = 0; f < frames; ++f) {
    ASSERT_EQ(r.peerA[f], r.reference[f]) << "peer A differs at frame " << f + 1;
    ASSERT_EQ(r.peerB[f], r.reference[f]) << "peer B differs at frame " << f + 1;
  }
  // The scenario did what it is for: predictions were wrong and rolled back, several frames
  // deep, shots came and went, and the pile slept.
  EXPECT_GT(r.rollbacks, 20u);
  EXPECT_GE(r.deepest, 3u);
  EXPECT_GT(r.mostShots, 2u);
  EXPECT_GT(r.mostAsleep, 10u);
}

TEST(RollbackPeers, ConfirmedFramesMatchTheReferenceOverAJitteryLink) {
  ExpectPeersAgree({3, 4, 1}, 600, 1);
}

TEST(RollbackPeers, ConfirmedFramesMatchWithAPeerOnTwoThreads) {
  ExpectPeersAgree({2, 6, 2}, 600, 2);
}

TEST(RollbackPeers, ALongDelayMakesPeersWaitAndStillAgree) {
  // 10 ticks each way: beyond the 8 frames a peer may predict, so it waits.
  const rollback::SessionResult r = rollback::PlaySession(300, {10, 3, 3}, 8, 1);
  EXPECT_EQ(r.firstMismatch, 0u);
  EXPECT_GT(r.stalls, 0u);
  EXPECT_GT(r.rollbacks, 5u);
}

}  // namespace
