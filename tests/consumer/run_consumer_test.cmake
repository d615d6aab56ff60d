# A game's builds against REngine (cmake -P, from ctest's install_consumer):
#   1. REngine installed from the build tree BUILD_DIR into a scratch prefix; the consumer
#      finds it with find_package and is built three ways: default flags, -mavx2 -mfma, and
#      -march=native (the last two only where the processor runs AVX2). Each runs a ball, a
#      compound, a hull and a joint and checks their closed forms.
#   2. A build that defeats the alignment REngine::Math pins (-mavx2 with
#      EIGEN_MAX_STATIC_ALIGN_BYTES undefined) must stop at start-up with RAbi.h's message,
#      not run on mismatched layouts.
#   3. The Scene component.
#   4. REngine as a subproject: add_subdirectory of SOURCE_DIR configured (the libraries only,
#      no developer targets), and FetchContent from the git repository at SOURCE_DIR built and
#      run (Debug: a game's debug build, and the quickest build of the engine's sources).
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
macro(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endmacro()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

file(READ /proc/cpuinfo cpuinfo)
string(FIND "${cpuinfo}" " avx2" avx2_at)
set(flavours default)
if(avx2_at GREATER -1)
  list(APPEND flavours avx2 native)
else()
  message(STATUS "no AVX2 on this processor: the -mavx2 and -march=native consumers are skipped")
endif()
set(flags_default "")
set(flags_avx2 "-mavx2 -mfma")
set(flags_native "-march=native")
foreach(f IN LISTS flavours)
  message(STATUS "consumer with CMAKE_CXX_FLAGS='${flags_${f}}'")
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/consumer_${f} -G ${GENERATOR}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} "-DCMAKE_CXX_FLAGS=${flags_${f}}"
      -DCMAKE_DISABLE_FIND_PACKAGE_nlohmann_json=ON)
  run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer_${f})
  run(${WORK_DIR}/consumer_${f}/consumer)
endforeach()

if(avx2_at GREATER -1)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/consumer_mismatch -G ${GENERATOR}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix}
      "-DCMAKE_CXX_FLAGS=-mavx2 -mfma -UEIGEN_MAX_STATIC_ALIGN_BYTES")
  run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer_mismatch)
  execute_process(COMMAND ${WORK_DIR}/consumer_mismatch/consumer RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0 OR NOT err MATCHES "REngine: ABI mismatch.*EIGEN_MAX_STATIC_ALIGN_BYTES is 32 here, 16 in the library")
    message(FATAL_ERROR "a consumer with mismatched layouts was not stopped (${rc}):\n${out}\n${err}")
  endif()
  message(STATUS "mismatched consumer stopped as it should:\n${err}")
endif()

run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/consumer_scene -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCONSUMER_SCENE=ON)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer_scene)
run(${WORK_DIR}/consumer_scene/consumer)
run(${WORK_DIR}/consumer_scene/consumer_scene)

run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/sub_add -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Debug -DCONSUMER_SUBPROJECT=add_subdirectory
    -DCONSUMER_REPOSITORY=${SOURCE_DIR})
if(EXISTS ${SOURCE_DIR}/.git)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/sub_fetch -G ${GENERATOR}
      -DCMAKE_BUILD_TYPE=Debug -DCONSUMER_SUBPROJECT=fetchcontent
      -DCONSUMER_REPOSITORY=file://${SOURCE_DIR} -DFETCHCONTENT_BASE_DIR=${WORK_DIR}/sub_fetch_deps)
  run(${CMAKE_COMMAND} --build ${WORK_DIR}/sub_fetch --target consumer)
  run(${WORK_DIR}/sub_fetch/consumer)
else()
  message(STATUS "${SOURCE_DIR} is not a git repository: the FetchContent consumer is skipped")
endif()
