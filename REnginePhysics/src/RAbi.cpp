// The library's side of the layout check (RAbi.h): the layouts as the library was compiled.
#include <REnginePhysics/RAbi.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RContactEvents.h>
#include <REnginePhysics/RConvexPolyhedron.h>
#include <REnginePhysics/RFreeRotation.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RJoint.h>
#include <REnginePhysics/RQueries.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RShape.h>
#include <REnginePhysics/RTriangleMesh.h>
#include <REnginePhysics/RWorldState.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace REngine {
namespace {

// Every type a public header checks, as the library sees it. A function-local table, so it is
// ready when another translation unit's static initialisation calls RVerifyAbi first.
const RAbiLayout* LibraryLayouts(std::size_t& count) {
  static const RAbiLayout kLibrary[] = {
      {"EIGEN_MAX_STATIC_ALIGN_BYTES", EIGEN_MAX_STATIC_ALIGN_BYTES, 0},
      RENGINE_ABI_LAYOUT(RQuat),
      RENGINE_ABI_LAYOUT(RVec4),
      RENGINE_ABI_LAYOUT(RShape),
      RENGINE_ABI_LAYOUT(RCompoundChild),
      RENGINE_ABI_LAYOUT(RMassProperties),
      RENGINE_ABI_LAYOUT(RPlane),
      RENGINE_ABI_LAYOUT(RFace),
      RENGINE_ABI_LAYOUT(REdge),
      RENGINE_ABI_LAYOUT(RPolyhedronMass),
      RENGINE_ABI_LAYOUT(RConvexPolyhedron),
      RENGINE_ABI_LAYOUT(RTriangleMesh),
      RENGINE_ABI_LAYOUT(RFreeRotation),
      RENGINE_ABI_LAYOUT(RConvexShape),
      RENGINE_ABI_LAYOUT(RShapeChild),
      RENGINE_ABI_LAYOUT(RRelativePose),
      RENGINE_ABI_LAYOUT(RDistanceResult),
      RENGINE_ABI_LAYOUT(RContactPoint),
      RENGINE_ABI_LAYOUT(RContactManifold),
      RENGINE_ABI_LAYOUT(RWorldForm),
      RENGINE_ABI_LAYOUT(RPreparedShape),
      RENGINE_ABI_LAYOUT(RBodyLocks),
      RENGINE_ABI_LAYOUT(RBodyDef),
      RENGINE_ABI_LAYOUT(RRigidBody),
      RENGINE_ABI_LAYOUT(RJointMotor),
      RENGINE_ABI_LAYOUT(RJointDef),
      RENGINE_ABI_LAYOUT(RJoint),
      RENGINE_ABI_LAYOUT(RBodies),
      RENGINE_ABI_LAYOUT(RContactEvent),
      RENGINE_ABI_LAYOUT(RWorldSettings),
      RENGINE_ABI_LAYOUT(RStepProfile),
      RENGINE_ABI_LAYOUT(RContact),
      RENGINE_ABI_LAYOUT(RPairStats),
      RENGINE_ABI_LAYOUT(RIntegrator),
      RENGINE_ABI_LAYOUT(RQueryFilter),
      RENGINE_ABI_LAYOUT(RRay),
      RENGINE_ABI_LAYOUT(RRayHit),
      RENGINE_ABI_LAYOUT(RShapeCastHit),
      RENGINE_ABI_LAYOUT(RShapeRayHit),
      RENGINE_ABI_LAYOUT(RShapeCastResult),
      RENGINE_ABI_LAYOUT(RQueries),
      RENGINE_ABI_LAYOUT(RLoadOptions),
      RENGINE_ABI_LAYOUT(RStateInfo),
  };
  count = std::size(kLibrary);
  return kLibrary;
}

}  // namespace

bool RVerifyAbi(const RAbiLayout* layouts, std::size_t count) noexcept {
  std::size_t libraryCount = 0;
  const RAbiLayout* library = LibraryLayouts(libraryCount);
  bool ok = true;
  for (std::size_t i = 0; i < count; ++i) {
    const RAbiLayout* mine = nullptr;
    for (std::size_t k = 0; k < libraryCount && !mine; ++k)
      if (std::strcmp(library[k].type, layouts[i].type) == 0) mine = &library[k];
    if (mine && mine->size == layouts[i].size && mine->align == layouts[i].align) continue;
    if (ok)
      std::fprintf(stderr,
                   "REngine: ABI mismatch between this program and the REngine library it links:\n");
    ok = false;
    if (mine)
      std::fprintf(stderr, "  %s: %zu bytes aligned to %zu here, %zu aligned to %zu in the library\n",
                   layouts[i].type, layouts[i].size, layouts[i].align, mine->size, mine->align);
    else
      std::fprintf(stderr, "  %s: unknown to the library (headers from another version?)\n",
                   layouts[i].type);
  }
  if (ok) return true;
  std::fprintf(stderr,
               "The usual cause is SIMD flags (-mavx2, -march=native) that change Eigen's alignment.\n"
               "Link REngine::Physics through CMake (it sets EIGEN_MAX_STATIC_ALIGN_BYTES=16), or\n"
               "compile every file that includes REngine's headers with "
               "-DEIGEN_MAX_STATIC_ALIGN_BYTES=16,\nand use the headers of the library you link.\n");
  std::abort();
}

}  // namespace REngine
