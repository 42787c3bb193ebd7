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
file(READ "${MANIFEST}" manifest)
string(JSON count LENGTH "${manifest}" images)
math(EXPR last "${count} - 1")
foreach(i RANGE ${last})
  string(JSON name GET "${manifest}" images ${i} name)
  string(JSON scene GET "${manifest}" images ${i} scene)
  string(JSON options GET "${manifest}" images ${i} options)
  string(JSON rmse GET "${manifest}" images ${i} tolerance max_rmse)
  string(JSON error GET "${manifest}" images ${i} tolerance max_error)
  string(JSON share GET "${manifest}" images ${i} tolerance max_share)
  string(JSON golden ERROR_VARIABLE missing GET "${manifest}" images ${i} golden)
  if(missing)
    set(golden "${name}")
  endif()
  string(JSON optimized_options ERROR_VARIABLE missing GET "${manifest}" images ${i} optimized_options)
  if(missing)
    set(optimized_options "${options}")
  endif()
  string(JSON modes ERROR_VARIABLE missing GET "${manifest}" images ${i} modes)
  if(missing)
    set(modes "mono packet omni frustum mft cone mft-cone")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E echo
                  "${name}|${scene}|${options}|${rmse}|${error}|${share}|${golden}|${optimized_options}|${modes}")
endforeach()
