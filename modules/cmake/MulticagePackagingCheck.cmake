# Run by cpack before it packs (CPACK_PRE_BUILD_SCRIPTS): Debian packages install into /usr,
# and the paths inside them (the Python module's folder) were fixed when the build was configured.
if(NOT CPACK_MULTICAGE_CONFIGURED_PREFIX STREQUAL "/usr")
    message(FATAL_ERROR "multicage: Debian packages need a build configured with "
        "-DCMAKE_INSTALL_PREFIX=/usr (this one has ${CPACK_MULTICAGE_CONFIGURED_PREFIX}); "
        "see docs/packaging.md")
endif()
