// rengine-sim --rays FILE (see rays.h).
#include "rays.h"

#include "csv.h"

#include <charconv>

namespace REngine::sim {

RayWriter::RayWriter(const RScene& scene, std::FILE* out) : m_scene(scene), m_out(out) {
  m_buffer = "step,ray,body,distance,x,y,z,nx,ny,nz\n";
}

void RayWriter::Answer(std::uint64_t step, const RSceneWorld& world) {
  const std::vector<RSceneRay>& rays = m_scene.rays;
  for (; m_next < rays.size() && rays[m_next].step <= step; ++m_next) {
    const RSceneRay& r = rays[m_next];
    // The loader checked what RQueries checks: these never throw.
    RQueryFilter filter;
    filter.mask = r.mask;
    const RRay ray{r.origin_W, r.direction_W, r.maxDistance};
    if (r.all) {
      m_queries.CastRayAll(world.Bodies(), ray, m_hits, filter);
    } else {
      m_hits.clear();
      if (const auto hit = m_queries.CastRay(world.Bodies(), ray, filter)) m_hits.push_back(*hit);
    }
    if (m_hits.empty()) Row(step, r, nullptr, world);
    for (const RRayHit& hit : m_hits) Row(step, r, &hit, world);
  }
  if (m_buffer.size() >= (std::size_t(1) << 20)) Flush();
}

void RayWriter::Row(std::uint64_t step, const RSceneRay& ray, const RRayHit* hit,
                    const RSceneWorld& world) {
  m_buffer += std::to_string(step);
  m_buffer += ',';
  m_buffer += CsvField(ray.name);
  m_buffer += ',';
  if (!hit) {
    m_buffer += ",inf,,,,,,\n";
    return;
  }
  m_buffer += CsvField(world.Bodies()[hit->body].Name());
  Number(hit->distance);
  for (int a = 0; a < 3; ++a) Number(hit->point_W[a]);
  for (int a = 0; a < 3; ++a) Number(hit->normal_W[a]);
  m_buffer += '\n';
}

// %.17g, as the trajectory's numbers (std::to_chars with that precision is defined so).
void RayWriter::Number(double value) {
  char text[40];
  text[0] = ',';
  const char* end =
      std::to_chars(text + 1, text + sizeof text, value, std::chars_format::general, 17).ptr;
  m_buffer.append(text, static_cast<std::size_t>(end - text));
}

bool RayWriter::Flush() {
  if (std::fwrite(m_buffer.data(), 1, m_buffer.size(), m_out) != m_buffer.size()) m_failed = true;
  m_buffer.clear();
  return !m_failed && std::fflush(m_out) == 0;
}

}  // namespace REngine::sim
