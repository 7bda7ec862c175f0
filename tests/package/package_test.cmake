# Script for Package.SampleBuildsAgainstInstalledPackage.
include(${CMAKE_CURRENT_LIST_DIR}/../common/install_to_scratch.cmake)
foreach(f include/opencv2/multicage.hpp include/opencv2/multicage/multicage.hpp bin/multicage)
    if(NOT EXISTS ${prefix}/${f})
        message(FATAL_ERROR "the install lacks ${f}")
    endif()
endforeach()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/samples/cpp -B ${WORK_DIR}/sample -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/sample)
run(${WORK_DIR}/sample/deform_example ${SOURCE_DIR}/samples/data/HappyFish.jpg ${WORK_DIR}/out.png)
if(NOT EXISTS ${WORK_DIR}/out.png)
    message(FATAL_ERROR "the sample wrote no image")
endif()
# The installed tool runs from its own prefix (RPATH) and teaches with --help.
run(${prefix}/bin/multicage --help)
message(STATUS "installed package OK")
