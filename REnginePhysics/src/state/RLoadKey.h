// The key to the subsystems' RestoreForLoad functions. A loaded state puts back what a step
// remembers (contact manifolds, warm starts, sleeping, events' touching pairs, the first
// body put back) exactly as it was saved, bypassing every check the step's own code keeps;
// only the loader (RStateAccess, which validates the whole state first) can make the key, so
// no other engine code restores a subsystem by accident.
#pragma once

namespace REngine {

struct RStateAccess;
struct RSnapshotAccess;

class RLoadKey {
  friend struct RStateAccess;
  friend struct RSnapshotAccess;  // rollback snapshots (RSnapshot.h), as checked when saved
  RLoadKey() {}  // (user-provided: RLoadKey{} is not an aggregate that bypasses it)
};

}  // namespace REngine
