# Sanitizer and fuzzer builds (issue 8). Included from the top-level CMakeLists.txt before any
# target exists, so the flags reach the library, the tools and every test.
#
#   cmake -S . -B build-asan -DMULTICAGE_SANITIZE=address,undefined -DMULTICAGE_BUILD_PYTHON=OFF
#   CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -DMULTICAGE_BUILD_FUZZERS=ON \
#       -DMULTICAGE_SANITIZE=address,undefined
#
# MULTICAGE_SANITIZE: a -fsanitize= list (address, undefined, address,undefined, thread, ...).
# UndefinedBehaviorSanitizer does not recover: the first report aborts the process, so a test
# with undefined behaviour fails instead of printing a line nobody reads.
# MULTICAGE_BUILD_FUZZERS (clang only): instruments everything for libFuzzer
# (-fsanitize=fuzzer-no-link) and builds the targets of tests/fuzz.
include_guard(GLOBAL)

set(MULTICAGE_SANITIZE "" CACHE STRING
    "Sanitizers for every target, as for -fsanitize= (e.g. address,undefined); empty: none")
option(MULTICAGE_BUILD_FUZZERS "Build the libFuzzer targets of tests/fuzz (clang only)" OFF)

if(MULTICAGE_SANITIZE)
    add_compile_options(-fsanitize=${MULTICAGE_SANITIZE} -fno-omit-frame-pointer -g)
    add_link_options(-fsanitize=${MULTICAGE_SANITIZE})
    if(MULTICAGE_SANITIZE MATCHES "undefined")
        add_compile_options(-fno-sanitize-recover=all)
        add_link_options(-fno-sanitize-recover=all)
    endif()
    message(STATUS "multicage: sanitizers ${MULTICAGE_SANITIZE} on every target")
endif()

if(MULTICAGE_BUILD_FUZZERS)
    if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
        message(FATAL_ERROR "MULTICAGE_BUILD_FUZZERS needs clang (libFuzzer); configure with "
            "CC=clang-14 CXX=clang++-14 (Debian: apt-get install clang-14 libclang-rt-14-dev)")
    endif()
    # Coverage feedback from the library too, not only from the fuzz targets' own code.
    add_compile_options(-fsanitize=fuzzer-no-link)
endif()
