# Shaders live beside the code that dispatches them (levelset/shaders/*.comp, ...). Each library embeds
# the shaders of its own folder at build time, so the executable runs from any directory and a library
# can compile only its own shaders (the dependency rule of DESIGN.md holds in the build too).
#   isoatlas_embed_shaders(TARGET SYMBOL [FOLDER])
# adds to TARGET a table `isoatlas::gl::SYMBOL` of the files in FOLDER (default: the calling folder's
# shaders/), looked up by their path from the repository root (e.g. "levelset/shaders/update.comp"), and a header
# <SYMBOL.h> declaring it.
set(ISOATLAS_SHADER_EXTENSIONS glsl comp vert frag tesc tese geom)

function(isoatlas_embed_shaders target symbol)
  set(folder "${CMAKE_CURRENT_SOURCE_DIR}/shaders")
  if(ARGC GREATER 2)
    set(folder "${ARGV2}")
  endif()
  set(globs "")
  foreach(ext IN LISTS ISOATLAS_SHADER_EXTENSIONS)
    list(APPEND globs "${folder}/*.${ext}")
  endforeach()
  file(GLOB shaders CONFIGURE_DEPENDS ${globs})
  set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/embedded_${symbol}")
  add_custom_command(
    OUTPUT ${out_dir}/${symbol}.cpp ${out_dir}/${symbol}.h
    COMMAND ${CMAKE_COMMAND} -DROOT=${PROJECT_SOURCE_DIR} -DOUT_DIR=${out_dir} -DSYMBOL=${symbol} "-DFILES=${shaders}"
            -P ${PROJECT_SOURCE_DIR}/cmake/embed_shaders_run.cmake
    DEPENDS ${shaders} ${PROJECT_SOURCE_DIR}/cmake/embed_shaders_run.cmake
    COMMENT "Embedding the shaders of ${target}"
    VERBATIM)
  target_sources(${target} PRIVATE ${out_dir}/${symbol}.cpp ${out_dir}/${symbol}.h)
  target_include_directories(${target} PRIVATE ${out_dir})
endfunction()
