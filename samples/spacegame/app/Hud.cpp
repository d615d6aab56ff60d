#include "Hud.h"

#include <imgui.h>

namespace spacegame {
using namespace REngine;

void DrawHud(const Game& game, const HudState& s, DebugDraw& debug) {
  const SpaceWorld& world = game.World();
  const RIntegrator& integrator = world.Integrator();
  const RStepProfile& p = integrator.Profile();
  const RPairStats& stats = integrator.PairStats();

  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.55f);
  ImGui::Begin("REngine", nullptr,
               ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoFocusOnAppearing);
  ImGui::Text("frame %llu  %.0f fps%s", static_cast<unsigned long long>(s.frame), s.framesPerSecond,
              s.autoplay ? "  (autoplay)" : "");
  ImGui::Text("steps %llu at %.1f Hz, physics %.3f ms/step",
              static_cast<unsigned long long>(game.Timing().steps), 1.0 / world.StepDt(),
              game.Timing().MsPerStep());
  ImGui::Separator();
  ImGui::Text("last step, ms");
  ImGui::Text("  collision detection %.3f", p.collisionDetection);
  ImGui::Text("  find impulses       %.3f", p.findImpulses);
  ImGui::Text("  update objects      %.3f", p.updateObjects);
  ImGui::Text("  contact events      %.3f", p.contactEvents);
  ImGui::Text("  total               %.3f", p.total);
  ImGui::Separator();
  ImGui::Text("bodies %zu  contacts %zu  sleeping %llu", world.Bodies().EnabledCount(),
              integrator.Contacts().size(), static_cast<unsigned long long>(stats.sleepingBodies));
  ImGui::Text("joints %zu  events %zu", world.Bodies().JointCount(), integrator.Events().size());
  ImGui::Text("missiles %d  explosions %llu  splits %llu", game.MissileSystem().InFlight(),
              static_cast<unsigned long long>(game.MissileSystem().ExplosionCount()),
              static_cast<unsigned long long>(game.LaserSystem().Splits()));
  const Docking& dock = game.DockingClamp();
  int port = -1;
  const double d = dock.NearestPort(port);
  if (dock.IsDocked()) {
    ImGui::Text("docked at port %d", dock.DockedPort());
  } else {
    ImGui::Text("port %d at %.0f m", port, d);
  }
  ImGui::Separator();
  // Momentum and angular momentum change only by what the game applies (thrust, beams,
  // blasts, bodies in and out: SpaceWorld's ledger) and by touching the kinematic station
  // or the static bay (and the bay's gravity); the residual is the rest. In open space
  // momentum's is rounding; angular momentum's also holds the split-impulse position
  // correction's drift (it moves overlapping bodies without changing their velocities, so
  // x cross m v changes: debris thrown out of a rock shows it).
  const Conservation now = world.Measure(), r = game.Residual();
  ImGui::Text("conservation (dynamic bodies)");
  ImGui::Text("  |P| %.4e kg m/s    residual %.2e", now.momentum_W.norm(), r.momentum_W.norm());
  ImGui::Text("  |L| %.4e kg m2/s   residual %.2e", now.angularMomentum_W.norm(),
              r.angularMomentum_W.norm());
  ImGui::Text("  E   %.4e J         change   %+.2e", now.kineticEnergy, r.kineticEnergy);
  ImGui::Separator();
  ImGui::Checkbox("contacts", &debug.contacts);
  ImGui::SameLine();
  ImGui::Checkbox("bounds", &debug.bounds);
  ImGui::SameLine();
  ImGui::Checkbox("sleeping", &debug.sleeping);
  ImGui::SameLine();
  ImGui::Checkbox("joints", &debug.joints);
  if (!s.autoplay) {
    ImGui::TextDisabled("W/S thrust  A/D yaw  up/down pitch  Q/E roll  space laser");
    ImGui::TextDisabled("F missile  G dock  C camera  1-4 debug  Esc quit");
  }
  ImGui::End();
}

}  // namespace spacegame
