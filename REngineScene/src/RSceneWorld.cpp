// A scene's world as it runs: bodies and joints in an RBodies, actions applied at their steps,
// joints named as the scene names them.
#include <REnginePhysics/RScene.h>

#include <algorithm>

namespace REngine {

RSceneWorld::RSceneWorld(const RScene& scene) : m_scene(&scene) {
  std::vector<RRigidBody> bodies = CreateBodies(scene);
  m_bodies.Reserve(bodies.size());
  m_live.reserve(bodies.size());
  for (RRigidBody& b : bodies) {
    m_idByName.emplace(b.Name(), m_nextId++);
    const RBodyHandle h = m_bodies.Add(std::move(b));
    m_byName.emplace(m_bodies[h].Name(), h);
    m_live.push_back(h);
  }
  // The joints, as the bodies stand at the start.
  for (const RSceneJoint& j : scene.joints) AddJoint(j, "");
  // The characters (their definitions were checked at load).
  m_characters.reserve(scene.characters.size());
  for (const RSceneCharacter& c : scene.characters) {
    try {
      m_characters.emplace_back(c.def);
    } catch (const RCharacterError& e) {
      throw RSceneError(m_scene->fileName, c.path + "." + e.Field(), e.Problem());
    }
  }
  m_nextInput.assign(scene.characters.size(), 0);
}

void RSceneWorld::UpdateCharacters(RScalar dt, const RVec3& gravity_W) {
  for (std::size_t i = 0; i < m_characters.size(); ++i) {
    try {
      m_characters[i].Update(m_bodies, m_queries, dt, gravity_W);
    } catch (const RCharacterError& e) {
      throw RSceneError(m_scene->fileName, m_scene->characters[i].path + "." + e.Field(), e.Problem());
    }
  }
}

RBodyHandle RSceneWorld::Find(const std::string& name) const {
  const auto it = m_byName.find(name);
  return it == m_byName.end() ? RBodyHandle{} : it->second;
}

RJointHandle RSceneWorld::FindJoint(const std::string& name) const {
  const auto it = m_jointByName.find(name);
  return it == m_jointByName.end() ? RJointHandle{} : it->second;
}

bool RSceneWorld::HoldsExactlyItsJoints() const {
  if (m_bodies.JointCount() != m_jointByName.size()) return false;
  for (const auto& named : m_jointByName) {
    if (!m_bodies.ContainsJoint(named.second)) return false;
  }
  return true;
}

// The loader made every check AddJoint makes, against the bodies that exist where the joint is
// made; should AddJoint still refuse (a scene put together in code), the joint's path names it.
void RSceneWorld::AddJoint(const RSceneJoint& j, const std::string& when) {
  RJointDef def = j.def;
  def.a = m_byName.at(j.a);
  if (!j.b.empty()) def.b = m_byName.at(j.b);
  RJointHandle h;
  try {
    h = m_bodies.AddJoint(def);
  } catch (const RJointError& e) {
    throw RSceneError(m_scene->fileName, j.path + "." + e.Field(), e.Problem() + when);
  }
  m_jointByName[j.name] = h;
  if (h.index >= m_jointNameOfSlot.size()) m_jointNameOfSlot.resize(h.index + 1);
  m_jointNameOfSlot[h.index] = j.name;
}

// RBodies::Remove takes the body's joints along; their names go with them. (A scan of the
// joints, as RBodies' own removal makes. A joint the game added to the bodies itself has no
// name to forget.)
void RSceneWorld::RemoveBody(RBodyHandle h) {
  for (std::size_t k = 0; k < m_bodies.JointCount(); ++k) {
    const RJoint& j = m_bodies.JointAt(k);
    const RJointHandle jh = m_bodies.JointHandleAt(k);
    if ((j.def.a != h && j.def.b != h) || jh.index >= m_jointNameOfSlot.size()) continue;
    const auto named = m_jointByName.find(m_jointNameOfSlot[jh.index]);
    if (named != m_jointByName.end() && named->second == jh) m_jointByName.erase(named);
  }
  m_bodies.Remove(h);
}

void RSceneWorld::ApplyActions(std::uint64_t stepsRun) {
  for (std::size_t i = 0; i < m_characters.size(); ++i) {
    const std::vector<RSceneCharacter::Input>& inputs = m_scene->characters[i].inputs;
    for (std::size_t& k = m_nextInput[i]; k < inputs.size() && inputs[k].step <= stepsRun; ++k) {
      m_characters[i].SetDesiredVelocity(inputs[k].velocity_W);
      if (inputs[k].jump > 0) m_characters[i].Jump(inputs[k].jump);
    }
  }
  const std::vector<RSceneAction>& actions = m_scene->actions;
  for (; m_nextAction < actions.size() && actions[m_nextAction].step <= stepsRun; ++m_nextAction) {
    const RSceneAction& a = actions[m_nextAction];
    // The loader checked every name against the bodies and joints that exist at its step.
    std::string field;
    try {
      switch (a.verb) {
        case RSceneAction::Verb::kAdd: {
          field = "add";
          RBodyDef def = a.def;
          const std::uint32_t id = m_nextId++;
          def.id = id;
          for (const std::string& other : a.ignore) def.ignore.push_back(m_idByName.at(other));
          const RBodyHandle h = m_bodies.Add(def);
          // Ignoring is symmetric: the bodies it names learn to ignore it too.
          for (const std::string& other : a.ignore) {
            m_bodies[m_byName.at(other)].IgnoreCollisionsWith(id);
          }
          m_idByName[a.body] = id;
          m_byName.emplace(a.body, h);
          m_live.push_back(h);
          break;
        }
        case RSceneAction::Verb::kRemove: {
          field = "remove";
          const RBodyHandle h = m_byName.at(a.body);
          RemoveBody(h);
          m_byName.erase(a.body);
          m_live.erase(std::find(m_live.begin(), m_live.end(), h));
          break;
        }
        case RSceneAction::Verb::kImpulse: {
          field = "impulse";
          RRigidBody& b = m_bodies[m_byName.at(a.body)];
          if (a.point_W) {
            b.AddImpulseAtPoint_W(a.impulse_W, *a.point_W);
          } else {
            b.AddImpulse_W(a.impulse_W);
          }
          break;
        }
        case RSceneAction::Verb::kSetVelocity: {
          field = "set_velocity";
          RRigidBody& b = m_bodies[m_byName.at(a.body)];
          if (a.velocity_W) b.SetVelocity_W(*a.velocity_W);
          if (a.angularVelocity_W) b.SetAngularVelocity_W(*a.angularVelocity_W);
          break;
        }
        // As the bodies stand now: the joint keeps its anchors and axis in their frames.
        case RSceneAction::Verb::kAddJoint:
          AddJoint(a.joint, " (at step " + std::to_string(a.step) + ")");
          break;
        case RSceneAction::Verb::kRemoveJoint: {
          m_bodies.RemoveJoint(m_jointByName.at(a.joint.name));
          m_jointByName.erase(a.joint.name);
          break;
        }
      }
    } catch (const RBodyError& e) {
      throw RSceneError(m_scene->fileName, a.path + "." + field + "." + e.Field(),
                        e.Problem() + " (at step " + std::to_string(a.step) + ")");
    }
  }
}

}  // namespace REngine
