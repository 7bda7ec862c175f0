# Debian packages: `cpack -G DEB` in a build configured with -DCMAKE_INSTALL_PREFIX=/usr makes
# one package per install component (docs/packaging.md has the recipe and the smoke test):
#   libmulticage-dev   the library, its headers and CMake package, the segmenter model
#   multicage-tools    multicage and multicage-editor
#   python3-multicage  import multicage
#   multicage-samples  the samples and their photos, in /usr/share/multicage/samples
set(CPACK_PACKAGE_NAME multicage)
set(CPACK_PACKAGE_VENDOR multicage)
set(CPACK_PACKAGE_CONTACT "multicage developers <multicage@invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Multicage image deformation: bind once, deform in real time, nested cages kept intact")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL library tools python samples)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
# Shared-library dependencies from dpkg-shlibdeps (Debian package dpkg-dev); libmulticage
# itself is found in this build, not in an installed package.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${CMAKE_BINARY_DIR}/lib)
# ... so the packages that link it depend on it by name: CPACK_COMPONENT_<C>_DEPENDS below.
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)

set(CPACK_DEBIAN_LIBRARY_PACKAGE_NAME libmulticage-dev)
# The public headers include OpenCV's; GPU work needs Mesa's EGL (a GPU's own driver, or
# llvmpipe), faces OpenCV's cascades: without them the CPU and the classic cues are used.
# A build with MULTICAGE_WITH_GPU=OFF uses no EGL at all.
set(CPACK_DEBIAN_LIBRARY_PACKAGE_DEPENDS "libopencv-dev")
if(MULTICAGE_WITH_GPU)
    set(CPACK_DEBIAN_LIBRARY_PACKAGE_RECOMMENDS "libegl-mesa0, libgl1-mesa-dri, opencv-data")
else()
    set(CPACK_DEBIAN_LIBRARY_PACKAGE_RECOMMENDS "opencv-data")
endif()
set(CPACK_COMPONENT_LIBRARY_DESCRIPTION "the multicage library, headers and CMake package")

set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME multicage-tools)
set(CPACK_COMPONENT_TOOLS_DEPENDS library)
set(CPACK_COMPONENT_TOOLS_DESCRIPTION "multicage (demo, propose, resize, deform, pose, animate) and multicage-editor")

set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-multicage)
set(CPACK_COMPONENT_PYTHON_DEPENDS library)
set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS "python3, python3-numpy, python3-opencv")
set(CPACK_COMPONENT_PYTHON_DESCRIPTION "the multicage Python module (import multicage)")

set(CPACK_DEBIAN_SAMPLES_PACKAGE_NAME multicage-samples)
set(CPACK_DEBIAN_SAMPLES_PACKAGE_ARCHITECTURE all)
set(CPACK_DEBIAN_SAMPLES_PACKAGE_RECOMMENDS "multicage-tools, python3-multicage")
set(CPACK_COMPONENT_SAMPLES_DESCRIPTION "multicage samples (C++, Python) and their photos")

# A package built for another prefix would put the Python module where python3 does not look.
set(CPACK_MULTICAGE_CONFIGURED_PREFIX ${CMAKE_INSTALL_PREFIX})
set(CPACK_PRE_BUILD_SCRIPTS ${CMAKE_CURRENT_LIST_DIR}/MulticagePackagingCheck.cmake)
include(CPack)
