# Finds what the Python module needs and defines MULTICAGE_BUILD_PYTHON (default ON when found).
# Included from the top-level CMakeLists.txt and from tests/python (imported targets are
# directory-scoped, so each includer finds them again; the results are cached).

# Debian's python3 carries numpy, cv2 and pybind11; another python3 earlier on PATH may not.
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python the multicage module is built for")
endif()
find_package(Python3 QUIET COMPONENTS Interpreter Development.Module NumPy)
if(Python3_FOUND AND Python3_NumPy_FOUND)
    find_package(pybind11 2.6 CONFIG QUIET)
endif()
set(_multicage_python_default OFF)
if(Python3_FOUND AND Python3_NumPy_FOUND AND pybind11_FOUND)
    set(_multicage_python_default ON)
endif()
option(MULTICAGE_BUILD_PYTHON "Build the Python module (pybind11, numpy)" ${_multicage_python_default})
if(MULTICAGE_BUILD_PYTHON AND NOT (Python3_FOUND AND Python3_NumPy_FOUND AND pybind11_FOUND))
    message(FATAL_ERROR "MULTICAGE_BUILD_PYTHON needs pybind11 and a python3 with numpy "
        "(Debian: apt-get install pybind11-dev python3-dev python3-numpy); found python "
        "'${Python3_EXECUTABLE}' numpy=${Python3_NumPy_FOUND} pybind11=${pybind11_FOUND}")
endif()

# Where `cmake --install` puts the package, relative to the prefix: the folder Debian's python3
# searches for that prefix (/usr: lib/python3/dist-packages, /usr/local and others:
# lib/python3.X/dist-packages). Other prefixes need PYTHONPATH set to it.
if(MULTICAGE_BUILD_PYTHON AND NOT MULTICAGE_PYTHON_INSTALL_DIR)
    if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
        set(_multicage_pydir lib/python3/dist-packages)
    else()
        set(_multicage_pydir
            lib/python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}/dist-packages)
    endif()
    set(MULTICAGE_PYTHON_INSTALL_DIR ${_multicage_pydir} CACHE STRING
        "Install folder of the Python package, relative to the install prefix")
endif()
# The package in the build tree: PYTHONPATH=${MULTICAGE_PYTHON_BUILD_DIR} imports it.
set(MULTICAGE_PYTHON_BUILD_DIR ${CMAKE_BINARY_DIR}/python)
