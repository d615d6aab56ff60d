// Triangles to draw a collision shape with: the renderer draws exactly what collides.
// Positions and normals in the shape's own frame S (RShape), as floats: a shape is a few
// metres to a hundred across, so float keeps its detail; the 1e6 m of where it is never
// enters these numbers (Renderer.cpp draws relative to the camera).
#pragma once

#include <REnginePhysics/RShape.h>

#include <vector>

namespace spacegame {

struct MeshVertex {
  float position[3];
  float normal[3];
};

// Flat-shaded faces for boxes and hulls (one normal per face), smooth ones for the round
// shapes; a compound's children placed in S; a triangle mesh two-sided (each triangle
// twice, facing both ways, as the engine's triangles collide on both sides).
std::vector<MeshVertex> Tessellate(const REngine::RShape& shape);

}  // namespace spacegame
