// Private to REnginePhysics: the integrator's working state, behind RIntegrator (which holds
// one through a pointer, so none of this is in an installed header). It holds one of each
// subsystem (docs/ARCHITECTURE.md, "Subsystems and folders": the motion, the pair sweep, the
// broad phase, the contact solver with its joint solver, sleeping, the contact events, the
// weld groups), each of which owns its state behind its own header, and RIntegrator.cpp
// runs them in the step's order, handing each what it reads of the others as parameters.
// Stages that run as tasks (RJobSystem, m_jobs and m_tasks) write only their own outputs:
// per-task scratch, or slots counted beforehand; the results do not depend on the threads.
#pragma once

#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RJobSystem.h>
#include <REnginePhysics/RJoint.h>

#include "events/RContactEventLog.h"
#include "pairs/RBoundsTree.h"
#include "pairs/RBroadPhase.h"
#include "pairs/RPairSweep.h"
#include "body/RBodyAccess.h"
#include "joints/RJointSparse.h"
#include "joints/RJointTypes.h"
#include "joints/RWeldGroups.h"
#include "motion/RMotion.h"
#include "sleep/RSleeping.h"
#include "solver/RContactMaterials.h"
#include "solver/RContactSolver.h"
#include "solver/RSolverTypes.h"
#include "world/RStepBodies.h"
#include "world/RUnionFind.h"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace REngine {

class RWorldStep {
 public:
  // The motion (motion/RMotion.h): the step's one definition of the bodies' velocities (its
  // static functions), Integrate, and the bodies put back.
  RMotion m_motion;

  // The pair sweep (pairs/RPairSweep.h): the step's contacts, found with the broad phase.
  RPairSweep m_sweep;
  RBroadPhase m_broad;  // the broad phase (pairs/RBroadPhase.h): stage 1 with a tree
  // The step's job system (null: one thread) and how many tasks a parallel stage is cut
  // into (1 on one thread). Set by RIntegrator before each step.
  RJobSystem* m_jobs = nullptr;
  std::size_t m_tasks = 1;

  RWorldSettings m_settings;
  RStepProfile m_profile;
  std::uint64_t m_stepCount = 0;
  std::uint64_t m_cacheStamp = 0;
  // The contact solver (solver/RContactSolver.h), with the joint solver it drives
  // (joints/RJointSolver.h): FindImpulses, called from CollisionDetection.
  RContactSolver m_solver;
  // Each contact's material (solver/RContactMaterials.h): one-way bodies and the game's
  // contact callback, decided for new contacts before the solver.
  RContactMaterials m_materials;
  RSleeping m_sleep;  // sleeping islands (sleep/RSleeping.h)
  // Contact events (RWorldSettings::contactEvents): poses before the motion, events after.
  RContactEventLog m_eventLog;
  // Identity handles for the plain-vector path (RStepBodies::byIndex).
  std::vector<RBodyHandle> m_indexHandles;
  std::vector<std::uint32_t> m_indexSlots;

  // Welds (joints/RWeldGroups.h): the fixed joints' bodies in groups moved as one rigid body.
  RWeldGroups m_welds;
};

}  // namespace REngine
