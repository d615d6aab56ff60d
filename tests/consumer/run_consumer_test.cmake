# Installs REngine from SOURCE_DIR into a scratch prefix, then configures, builds and runs
# the consumer project against it, as a game's build would.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
macro(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endmacro()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/engine -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DRENGINE_BUILD_TESTS=OFF -DRENGINE_BUILD_TOOLS=OFF
    -DRENGINE_INSTALL=ON -DCMAKE_INSTALL_PREFIX=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/engine)
run(${CMAKE_COMMAND} --install ${WORK_DIR}/engine)
# A game that links only the physics: nlohmann_json must not be needed, so it is made
# unfindable.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/consumer -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_DISABLE_FIND_PACKAGE_nlohmann_json=ON)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)
run(${WORK_DIR}/consumer/consumer)
# A game (or tool) that reads scene files too.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/consumer_scene -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCONSUMER_SCENE=ON)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer_scene)
run(${WORK_DIR}/consumer_scene/consumer)
run(${WORK_DIR}/consumer_scene/consumer_scene)
