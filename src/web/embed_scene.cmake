# sweeps/live.toml into a C++ source (src/web/live_scene.cpp.in), at configure time; the file is
# a configure dependency, so an edit of it reconfigures. Used by the native and the wasm build.
function(ajx_embed_live_scene source_dir out)
  set(scene ${source_dir}/sweeps/live.toml)
  file(READ ${scene} AJX_LIVE_SCENE)
  if(AJX_LIVE_SCENE MATCHES "\\)ajx_live\"")
    message(FATAL_ERROR "${scene} contains the raw string's delimiter )ajx_live\"")
  endif()
  configure_file(${source_dir}/src/web/live_scene.cpp.in ${out} @ONLY)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${scene})
endfunction()
