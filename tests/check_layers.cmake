# The layers of src/, lowest first: a source of one layer may include its own layer's headers
# and those of lower ranks only (never a sibling of the same rank, never one above). Run at
# configure time by the top CMakeLists (an upward include stops the configuration) and as the
# test `layers` on a tree with a planted upward include, to show that it fails.
#   cmake -DSRC=<a src/ folder> -P tests/check_layers.cmake
#
#   0  numerics, io, parallel   the integrators; HDF5 and the journal; the MPI farm (no physics)
#   1  physics                  the model: drive, string, friction, contact modes
#   2  sim, orbits              integrating a run; steady orbits of the co-rotating frame
#   3  sweep                    protocols, tasks, the orbit classifier, thresholds
#   4  config                   files and overrides into the model, runs and sweeps
#   5  bench, results           work-precision and stability studies; run and sweep files
#   6  app, web                 the commands; the live page's engine (WebAssembly)
set(AJX_LAYER_numerics 0)
set(AJX_LAYER_io 0)
set(AJX_LAYER_parallel 0)
set(AJX_LAYER_physics 1)
set(AJX_LAYER_sim 2)
set(AJX_LAYER_orbits 2)
set(AJX_LAYER_sweep 3)
set(AJX_LAYER_config 4)
set(AJX_LAYER_bench 5)
set(AJX_LAYER_results 5)
set(AJX_LAYER_app 6)
set(AJX_LAYER_web 6)

# Known exceptions, each "file -> layer": to be removed, not added to. None today.
set(AJX_LAYER_EXCEPTIONS "")

if(NOT SRC)
  message(FATAL_ERROR "check_layers: give -DSRC=<src folder>")
endif()
get_filename_component(SRC "${SRC}" ABSOLUTE)
file(GLOB_RECURSE sources RELATIVE "${SRC}" "${SRC}/*.hpp" "${SRC}/*.cpp")
set(violations "")
foreach(f IN LISTS sources)
  string(REGEX MATCH "^[a-z_]+" layer "${f}")
  if(NOT DEFINED AJX_LAYER_${layer})
    continue()  # not in a layer folder (e.g. a main file at the top)
  endif()
  file(STRINGS "${SRC}/${f}" includes REGEX "^[ \t]*#[ \t]*include[ \t]+\"[a-z_]+/")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]+\"([a-z_]+)/.*" "\\1" target "${line}")
    if(target STREQUAL layer OR NOT DEFINED AJX_LAYER_${target})
      continue()
    endif()
    if(AJX_LAYER_${target} LESS AJX_LAYER_${layer})
      continue()
    endif()
    list(FIND AJX_LAYER_EXCEPTIONS "${f} -> ${target}" known)
    if(known EQUAL -1)
      list(APPEND violations "${f} (layer ${layer}, rank ${AJX_LAYER_${layer}}) includes ${target} (rank ${AJX_LAYER_${target}})")
    endif()
  endforeach()
endforeach()
if(violations)
  list(JOIN violations "\n  " text)
  message(FATAL_ERROR "upward or sibling includes between the layers of src/ (tests/check_layers.cmake):\n  ${text}")
endif()
