# Shaders live beside the code that dispatches them (levelset/shaders/*.comp, ...). They are embedded
# into one generated source at build time, so the executable runs from any directory. A shader is
# looked up by its path from the repository root, e.g. "tests/gl/shaders/double.comp".
set(ISOATLAS_SHADER_PATTERNS "*/shaders/*.glsl" "*/shaders/*.comp" "*/shaders/*.vert" "*/shaders/*.frag"
    "*/shaders/*.tesc" "*/shaders/*.tese" "*/shaders/*.geom")

function(isoatlas_embed_shaders out_cpp)
  set(globs "")
  foreach(p IN LISTS ISOATLAS_SHADER_PATTERNS)
    list(APPEND globs "${PROJECT_SOURCE_DIR}/${p}" "${PROJECT_SOURCE_DIR}/*/${p}")
  endforeach()
  file(GLOB shaders CONFIGURE_DEPENDS ${globs})
  add_custom_command(
    OUTPUT ${out_cpp}
    COMMAND ${CMAKE_COMMAND} -DROOT=${PROJECT_SOURCE_DIR} -DOUT=${out_cpp} "-DFILES=${shaders}"
            -P ${PROJECT_SOURCE_DIR}/cmake/embed_shaders_run.cmake
    DEPENDS ${shaders} ${PROJECT_SOURCE_DIR}/cmake/embed_shaders_run.cmake
    COMMENT "Embedding shaders"
    VERBATIM)
endfunction()
