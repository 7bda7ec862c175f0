# The API reference (issue 41): Doxygen over the public headers, HTML into <build>/doc/html.
# Included from the top-level CMakeLists.txt; the target is not part of ALL:
#
#   cmake --build build --target doc      # then open build/doc/html/index.html
#
# docs/Doxyfile.in turns every doxygen warning into a failure (WARN_AS_ERROR), so CI (.ci/run)
# fails on an undocumented declaration. Without doxygen (Debian package doxygen) there is no
# `doc` target, only a status line.
#
# Also runs as a script, writing the Doxyfile without configuring a build tree:
#   cmake -DMULTICAGE_DOC_OUTPUT_DIR=/tmp/multicage-doc -P modules/cmake/MulticageDoc.cmake
#   doxygen /tmp/multicage-doc/Doxyfile
include_guard(GLOBAL)

# Writes <outputDir>/Doxyfile from docs/Doxyfile.in for the source tree sourceDir; doxygen then
# writes the HTML to <outputDir>/html.
function(multicage_configure_doxyfile sourceDir outputDir)
    set(PROJECT_SOURCE_DIR ${sourceDir})
    set(MULTICAGE_DOC_OUTPUT_DIR ${outputDir})
    # Each module's include folder, so a class page says #include <opencv2/multicage/...>.
    file(GLOB includeDirs LIST_DIRECTORIES true ${sourceDir}/modules/include
         ${sourceDir}/modules/*/include)
    list(FILTER includeDirs EXCLUDE REGEX "/python/")
    list(JOIN includeDirs " " MULTICAGE_DOC_INCLUDE_DIRS)
    configure_file(${sourceDir}/docs/Doxyfile.in ${outputDir}/Doxyfile @ONLY)
endfunction()

if(CMAKE_SCRIPT_MODE_FILE)
    if(NOT MULTICAGE_DOC_OUTPUT_DIR)
        message(FATAL_ERROR "MulticageDoc.cmake: pass -DMULTICAGE_DOC_OUTPUT_DIR=<folder>")
    endif()
    get_filename_component(sourceDir ${CMAKE_CURRENT_LIST_DIR}/../.. ABSOLUTE)
    file(STRINGS ${sourceDir}/CMakeLists.txt projectLine REGEX "^project\\(multicage VERSION")
    string(REGEX MATCH "[0-9]+\\.[0-9]+\\.[0-9]+" PROJECT_VERSION "${projectLine}")
    multicage_configure_doxyfile(${sourceDir} ${MULTICAGE_DOC_OUTPUT_DIR})
    message(STATUS "MulticageDoc.cmake: wrote ${MULTICAGE_DOC_OUTPUT_DIR}/Doxyfile")
    return()
endif()

find_package(Doxygen QUIET)
if(DOXYGEN_FOUND)
    multicage_configure_doxyfile(${PROJECT_SOURCE_DIR} ${CMAKE_BINARY_DIR}/doc)
    add_custom_target(doc
        COMMAND Doxygen::doxygen ${CMAKE_BINARY_DIR}/doc/Doxyfile
        WORKING_DIRECTORY ${CMAKE_BINARY_DIR}/doc
        COMMENT "API reference: doxygen -> ${CMAKE_BINARY_DIR}/doc/html (a warning fails)"
        VERBATIM)
else()
    message(STATUS "multicage: doxygen not found, no `doc` target for the API reference "
                   "(apt-get install doxygen)")
endif()
