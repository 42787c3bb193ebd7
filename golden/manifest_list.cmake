# Prints golden/manifest.json one image per line, fields separated by '|':
#   name|scene|reference options|max_rmse|max_error|max_share|golden|optimized options|modes
# golden, optimized options and modes are optional in the manifest: an entry
# compared with another entry's image ("golden": "light_sphere-multi16", e.g.
# cone:16 against the reference's multi:16 with the same samples) renders the
# optimized image with "optimized_options"; "modes" narrows the traversal
# modes (default: all seven).
# so that shell scripts read the manifest without a JSON tool:
#   cmake -DMANIFEST=golden/manifest.json -P golden/manifest_list.cmake
# (CMake's string(JSON) is the parser; CMake is already a build dependency.)
include(${CMAKE_CURRENT_LIST_DIR}/manifest.cmake)
file(READ "${MANIFEST}" manifest)
string(JSON count LENGTH "${manifest}" images)
math(EXPR last "${count} - 1")
foreach(i RANGE ${last})
  rtt_golden_entry("${manifest}" ${i})
  string(REPLACE ";" " " modes "${golden_modes}")
  execute_process(COMMAND ${CMAKE_COMMAND} -E echo
                  "${golden_name}|${golden_scene}|${golden_options}|${golden_max_rmse}|${golden_max_error}|${golden_max_share}|${golden_image}|${golden_optimized_options}|${modes}")
endforeach()
