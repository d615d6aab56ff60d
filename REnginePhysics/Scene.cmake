# REngine::Scene: reads and validates scene files (docs/scene-format.md). A library of
# its own so that a game linking REngine::Physics does not pull in a JSON parser.
# A game that takes REngine as a subproject without nlohmann_json gets the physics alone.
if(REENGINE_IS_TOP)
  find_package(nlohmann_json 3 REQUIRED)
else()
  find_package(nlohmann_json 3 QUIET)
  if(NOT nlohmann_json_FOUND)
    message(STATUS "REngine: nlohmann_json not found, REngine::Scene is not built")
    return()
  endif()
endif()

add_library(REngineScene src/RScene.cpp src/RSceneJson.cpp src/RSceneActions.cpp
  src/RSceneRays.cpp src/RSceneJoints.cpp src/RSceneWorld.cpp)
add_library(REngine::Scene ALIAS REngineScene)
rengine_unity(REngineScene)
set_target_properties(REngineScene PROPERTIES EXPORT_NAME Scene OUTPUT_NAME rengine_scene)
target_include_directories(REngineScene PUBLIC
  $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
target_link_libraries(REngineScene
  PUBLIC REngine::Physics
  PRIVATE nlohmann_json::nlohmann_json $<BUILD_INTERFACE:rengine_warnings>)

if(RENGINE_INSTALL)
  install(TARGETS REngineScene EXPORT REngineSceneTargets)
endif()
