# Prints golden/manifest.json one image per line, fields separated by '|':
#   name|scene|render options|max_rmse|max_error|max_share
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
  execute_process(COMMAND ${CMAKE_COMMAND} -E echo "${name}|${scene}|${options}|${rmse}|${error}|${share}")
endforeach()
