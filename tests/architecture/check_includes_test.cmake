# The module-boundary check (modules/cmake/MulticageCheckIncludes.cmake) run two ways:
#   on the real modules/ tree, which must pass (as at configure time), and
#   on a copy with one planted violation per rule, each of which must fail it.
# cmake -DSOURCE_DIR=<repo> -DWORK_DIR=<scratch> -P check_includes_test.cmake
cmake_minimum_required(VERSION 3.22)
include(${SOURCE_DIR}/modules/cmake/MulticageCheckIncludes.cmake)

set(MULTICAGE_MODULES core coords pack gpu deform propose animate)
set(MULTICAGE_DEPENDS_core "")
set(MULTICAGE_DEPENDS_coords core)
set(MULTICAGE_DEPENDS_pack coords)
set(MULTICAGE_DEPENDS_gpu pack)
set(MULTICAGE_DEPENDS_deform gpu)
set(MULTICAGE_DEPENDS_propose core)
set(MULTICAGE_DEPENDS_animate deform)

# Each case: a file to plant, and its content. The checker runs in a child cmake so that
# its FATAL_ERROR can be observed.
set(cases
    "deform/src/planted.cpp|#include \"gl_util.hpp\""
    "propose/src/planted.cpp|#include \"../../core/src/cage_file.cpp\""
    "propose/src/planted.cpp|#include <opencv2/multicage/deformer.hpp>"
    "coords/src/planted.cpp|#include <opencv2/multicage.hpp>")

function(run_check dir out)
    file(WRITE ${WORK_DIR}/run.cmake "cmake_minimum_required(VERSION 3.22)
include(${SOURCE_DIR}/modules/cmake/MulticageCheckIncludes.cmake)
set(MULTICAGE_MODULES ${MULTICAGE_MODULES})
")
    foreach(m IN LISTS MULTICAGE_MODULES)
        file(APPEND ${WORK_DIR}/run.cmake "set(MULTICAGE_DEPENDS_${m} \"${MULTICAGE_DEPENDS_${m}}\")\n")
    endforeach()
    file(APPEND ${WORK_DIR}/run.cmake "multicage_check_includes(${dir})\n")
    execute_process(COMMAND ${CMAKE_COMMAND} -P ${WORK_DIR}/run.cmake
                    RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
    set(${out} ${rc} PARENT_SCOPE)
    set(${out}_text "${err}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
run_check(${SOURCE_DIR}/modules real)
if(NOT real EQUAL 0)
    message(FATAL_ERROR "the real modules/ tree fails the check:\n${real_text}")
endif()

foreach(case IN LISTS cases)
    string(REPLACE "|" ";" parts "${case}")
    list(GET parts 0 file)
    list(GET parts 1 line)
    file(REMOVE_RECURSE ${WORK_DIR}/modules)
    file(COPY ${SOURCE_DIR}/modules DESTINATION ${WORK_DIR} PATTERN "*.cpp" EXCLUDE)
    file(WRITE ${WORK_DIR}/modules/${file} "${line}\n")
    run_check(${WORK_DIR}/modules planted)
    if(planted EQUAL 0)
        message(FATAL_ERROR "planted '${line}' in ${file}: the check did not fail")
    endif()
    string(FIND "${planted_text}" "${file}" named)
    if(named EQUAL -1)
        message(FATAL_ERROR "planted '${line}' in ${file}: the failure does not name the file:\n${planted_text}")
    endif()
    message(STATUS "refused as expected: ${file}: ${line}")
endforeach()
