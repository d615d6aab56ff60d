// rengine-sim --rays FILE: the scene's rays (docs/scene-format.md, "Rays") answered after their
// steps into the CSV step,ray,body,distance,x,y,z,nx,ny,nz.
#pragma once

#include <REnginePhysics/RQueries.h>
#include <REnginePhysics/RScene.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace REngine::sim {

class RayWriter {
 public:
  // Writes the header at once; `out` stays the caller's to close.
  RayWriter(const RScene& scene, std::FILE* out);
  // Answers the rays of step `step` (the world after that step's actions): one row per hit,
  // nearest first, or one row with an empty body and distance inf. Steps must come in order.
  void Answer(std::uint64_t step, const RSceneWorld& world);
  // Writes what is buffered; false when any write failed.
  bool Flush();

 private:
  void Row(std::uint64_t step, const RSceneRay& ray, const RRayHit* hit, const RSceneWorld& world);

  const RScene& m_scene;
  std::FILE* m_out;
  std::size_t m_next = 0;  // the first ray not yet answered (scene.rays is sorted by step)
  RQueries m_queries;
  std::vector<RRayHit> m_hits;
  std::string m_buffer;
  bool m_failed = false;
};

}  // namespace REngine::sim
