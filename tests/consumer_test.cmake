# Installs minksum into a scratch prefix, then configures, builds and runs a consumer project
# against it; and the same consumer against the build tree in place (its exported package, no
# install): run with -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=...
file(REMOVE_RECURSE ${WORK_DIR})
foreach(step
    "${CMAKE_COMMAND};--install;${BUILD_DIR};--prefix;${WORK_DIR}/prefix"
    "${CMAKE_COMMAND};-S;${SOURCE_DIR}/tests/consumer;-B;${WORK_DIR}/build;-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix;-DCMAKE_BUILD_TYPE=Release;-DMINKSUM_README=${SOURCE_DIR}/README.md"
    "${CMAKE_COMMAND};--build;${WORK_DIR}/build"
    "${WORK_DIR}/build/app"
    "${WORK_DIR}/build/readme_program"
    "${WORK_DIR}/prefix/bin/minksum;--version"
    "${CMAKE_COMMAND};-S;${SOURCE_DIR}/tests/consumer;-B;${WORK_DIR}/in-place;-Dminksum_DIR=${BUILD_DIR};-DCMAKE_BUILD_TYPE=Release;-DMINKSUM_README=${SOURCE_DIR}/README.md"
    "${CMAKE_COMMAND};--build;${WORK_DIR}/in-place"
    "${WORK_DIR}/in-place/readme_program")
  execute_process(COMMAND ${step} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "step failed (${rc}): ${step}\n${out}\n${err}")
  endif()
endforeach()
message(STATUS "consumer: ${out}")
