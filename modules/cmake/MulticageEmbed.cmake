# multicage_embed(TARGET NAME FILES...)
# Compiles files into TARGET as byte arrays so that installed binaries need no data files
# (shaders, the demo image). Generated at build time; a changed file regenerates the source.
#   namespace cv::multicage::embedded { std::string_view NAME(std::string_view file); }
# looks a file up by its base name; an unknown name returns an empty view.
function(multicage_embed target name)
    set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded_${name}.cpp)
    add_custom_command(
        OUTPUT ${out}
        COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DNAME=${name} "-DFILES=${ARGN}"
                -P ${CMAKE_SOURCE_DIR}/modules/cmake/MulticageEmbedGenerate.cmake
        DEPENDS ${ARGN} ${CMAKE_SOURCE_DIR}/modules/cmake/MulticageEmbedGenerate.cmake
        COMMENT "Embedding ${name} files"
        VERBATIM)
    target_sources(${target} PRIVATE ${out})
endfunction()
