// The library's side of the layout check (RAbi.h): the layouts as the library was compiled.
#include <REnginePhysics/RAbi.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RCharacter.h>
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RContactEvents.h>
#include <REnginePhysics/RConvexPolyhedron.h>
#include <REnginePhysics/RFracture.h>
#include <REnginePhysics/RFreeRotation.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RJoint.h>
#include <REnginePhysics/RQueries.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RShape.h>
#include <REnginePhysics/RSnapshot.h>
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
      RENGINE_ABI_EIGEN_LAYOUT
      RENGINE_ABI_TYPES_BODIES(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_CHARACTER(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_COLLISION(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_CONTACT_EVENTS(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_CONVEX_POLYHEDRON(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_FRACTURE(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_FREE_ROTATION(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_INTEGRATOR(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_JOINT(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_QUERIES(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_RIGID_BODY(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_SHAPE(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_SNAPSHOT(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_TRIANGLE_MESH(RENGINE_ABI_LAYOUT)
      RENGINE_ABI_TYPES_WORLD_STATE(RENGINE_ABI_LAYOUT)
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
    if (mine && mine->align == 0)  // a setting, not a type
      std::fprintf(stderr, "  %s is %zu here, %zu in the library\n", layouts[i].type,
                   layouts[i].size, mine->size);
    else if (mine)
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
