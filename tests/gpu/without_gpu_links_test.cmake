# MULTICAGE_WITH_GPU=OFF: nothing of EGL, OpenGL or libepoxy was looked for, included or linked.
#  - looked for: the build's CMakeCache.txt holds no entry of find_package(OpenGL), of
#    pkg_check_modules(EPOXY) or of the editor's GLFW;
#  - included: no object's header dependencies (ninja -t deps) are under EGL/, GL/, GLES*/,
#    KHR/ or epoxy/;
#  - linked: no file in FILES (the library, the tool, the Python module) has one of their
#    libraries among its NEEDED entries (readelf -d).
# cmake -DBUILD_DIR=... -DREADELF=... -DNINJA=<ninja, or empty> -DFILES="a;b" -P without_gpu_links_test.cmake
cmake_minimum_required(VERSION 3.16)
set(errors "")

file(STRINGS ${BUILD_DIR}/CMakeCache.txt cache REGEX "^(OPENGL_|OpenGL_|EPOXY_|_*pkg_config_checked_EPOXY|glfw3_)")
foreach(line IN LISTS cache)
    string(APPEND errors "CMakeCache.txt: ${line} (looked for though MULTICAGE_WITH_GPU=OFF)\n")
endforeach()

if(NINJA)
    execute_process(COMMAND ${NINJA} -C ${BUILD_DIR} -t deps OUTPUT_VARIABLE deps RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "ninja -t deps in ${BUILD_DIR} failed (${rc})")
    endif()
    string(REGEX MATCHALL "[^\n]*/(EGL|GL|GLES[0-9]*|KHR|epoxy)/[^\n/]+\\.h[^\n]*" headers "${deps}")
    list(TRANSFORM headers STRIP)
    list(REMOVE_DUPLICATES headers)
    foreach(h IN LISTS headers)
        string(APPEND errors "an object includes ${h}\n")
    endforeach()
endif()

foreach(f IN LISTS FILES)
    execute_process(COMMAND ${READELF} -d ${f} OUTPUT_VARIABLE dynamic RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "${READELF} -d ${f} failed (${rc})")
    endif()
    string(REGEX MATCHALL "\\(NEEDED\\)[^\n]*\\[[^]\n]+\\]" needed "${dynamic}")
    set(names "")
    foreach(n IN LISTS needed)
        string(REGEX REPLACE ".*\\[(.*)\\]" "\\1" n "${n}")
        list(APPEND names ${n})
        if(n MATCHES "^lib(EGL|GL|GLX|OpenGL|GLES|GLdispatch|epoxy|glfw|gbm)[.v0-9_]*\\.so")
            string(APPEND errors "${f} needs ${n}\n")
        endif()
    endforeach()
    list(JOIN names " " names)
    message(STATUS "${f} needs: ${names}")
endforeach()

if(errors)
    message(FATAL_ERROR "MULTICAGE_WITH_GPU=OFF, yet:\n${errors}")
endif()
