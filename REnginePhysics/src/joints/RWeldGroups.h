// Private to REnginePhysics: welds, the awake dynamic bodies joined by the step's fixed
// joints, in groups moved as the one rigid body each forms (RWeldGroups.cpp says why and
// how). Owns the step's groups: each group's members and their poses in its frame, its
// composite mass and principal inertia, and which group each body is in. The groups are
// built each step (GatherWelds, after the joint solver gathers the step's joints) and read
// only within it: the joint solver predicts a group's members as one (PredictWeld), the
// motion moves them as one (MoveWeld, instead of each member's own motion), and the joint
// and contact solvers ask which bodies are welded together (WeldOf, Welded, Root). What the
// functions read and write of the joint and contact solvers (the step's joints, the solver
// bodies, the joint poses) comes in as parameters, of those solvers' own types.
#pragma once

#include <REngineMath/RMath.h>

#include "joints/RJointTypes.h"
#include "solver/RSolverTypes.h"
#include "world/RUnionFind.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace REngine {

struct RStepBodies;
struct RWorldSettings;

class RWeldGroups {
 public:
  // Groups the awake dynamic bodies joined by the step's fixed joints. stepJoints: the joint
  // solver's joints of the step, each with its index into bodies.joints (joint) and its
  // bodies' dense indices (a, b; b = bodies.size() for a joint to the world).
  void GatherWelds(const RStepBodies& bodies, const std::vector<RStepJoint>& stepJoints);

  // This step's groups (after GatherWelds), and the group body i (a dense index) moves with:
  // an index below GroupCount(), or kNoWeld (also for the world's solver body, index
  // bodies.size()). Welded(i): whether it moves with one.
  static constexpr std::uint32_t kNoWeld = 0xffffffffu;
  std::size_t GroupCount() const { return m_weldGroups.size(); }
  std::uint32_t WeldOf(std::uint32_t i) const {
    return i >= m_weldOf.size() || m_weldOf[i] == 0 ? kNoWeld : m_weldOf[i] - 1;
  }
  bool Welded(std::size_t i) const { return i < m_weldOf.size() && m_weldOf[i] != 0; }
  // A group's first member, its root (a dense index): the group's frame is kept from the
  // root's orientation, and bodies in one group have the same root.
  std::uint32_t Root(std::uint32_t group) const {
    return m_weldMembers[m_weldGroups[group].first].body;
  }

  // One group's motion (from Integrate, instead of the members' own): the members' impulses,
  // forces, torques and the contact solver's outputs summed about the group's centre, the
  // composite moved as Integrate moves any body, each member placed on it. The solver's
  // outputs are read from solverBodies (per dense index) for members in its rows (inRows)
  // when it solved this step; a member of a group whose new state is not finite is marked in
  // putBack (per dense index). Groups share no body: they move side by side.
  void MoveWeld(const RStepBodies& bodies, std::size_t group, RScalar dt,
                const RWorldSettings& settings, const std::vector<RSolverBody>& solverBodies,
                const std::vector<char>& inRows, bool solved, std::vector<char>& putBack) const;
  // The group's members' end poses as MoveWeld will make them from the solver's velocities
  // (solverBodies, per dense index), written to their jointPoses (the joint solver's end
  // poses, per dense index): the joints' prediction for a weld's bodies.
  void PredictWeld(const RStepBodies& bodies, std::size_t group, RScalar dt,
                   const std::vector<RSolverBody>& solverBodies,
                   std::vector<RJointPose>& jointPoses) const;

 private:
  // A member's pose in its group's frame (principal axes at the group's centre of mass;
  // while grouping, the root's frame): q (q_CB) and p (m).
  struct RWeldMember {
    std::uint32_t body;
    RQuat q;
    RVec3 p;
  };
  struct RWeldGroup {
    std::uint32_t first = 0, count = 0;  // its members in m_weldMembers; the first is the root
    RScalar mass = 0;                    // kg
    RVec3 I = RVec3::Ones();             // principal moments, ascending, kg m^2
    RQuat q_RC = RQuat::Identity();      // the principal frame in the root's
  };
  // The group's centre of mass now, world, m.
  RVec3 Centre(const RStepBodies& bodies, const RWeldGroup& g) const;

  std::vector<RWeldGroup> m_weldGroups;
  std::vector<RWeldMember> m_weldMembers;
  // Per body: its group's index + 1, 0 for none (empty when there is no group).
  std::vector<std::uint32_t> m_weldOf;
  std::vector<std::uint32_t> m_weldJoints;  // (GatherWelds' scratch)
  RUnionFind m_weldSets;
};

}  // namespace REngine
