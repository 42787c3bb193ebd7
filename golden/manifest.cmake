# Reads entry `index` of golden/manifest.json (text in `manifest`) into the
# caller's variables, with the optional fields' defaults filled in:
#   golden_name, golden_scene, golden_options (the reference render's),
#   golden_max_rmse, golden_max_error, golden_max_share,
#   golden_image (the image compared with: another entry's, or its own),
#   golden_optimized_options (the optimized render's; default: the reference's),
#   golden_modes (a list; default: all seven kd traversal modes and pgrid,
#   the perspective grid's eye rays).
# Used by tests.cmake (the ctest cases) and manifest_list.cmake (the shell
# scripts), so both read the manifest the same way.
function(rtt_golden_entry manifest index)
  string(JSON name GET "${manifest}" images ${index} name)
  string(JSON options GET "${manifest}" images ${index} options)
  string(JSON image ERROR_VARIABLE missing GET "${manifest}" images ${index} golden)
  if(missing)
    set(image "${name}")
  endif()
  string(JSON optimized ERROR_VARIABLE missing GET "${manifest}" images ${index} optimized_options)
  if(missing)
    set(optimized "${options}")
  endif()
  string(JSON modes ERROR_VARIABLE missing GET "${manifest}" images ${index} modes)
  if(missing)
    set(modes "mono packet omni frustum mft cone mft-cone pgrid")
  endif()
  separate_arguments(modes UNIX_COMMAND "${modes}")
  string(JSON scene GET "${manifest}" images ${index} scene)
  string(JSON rmse GET "${manifest}" images ${index} tolerance max_rmse)
  string(JSON error GET "${manifest}" images ${index} tolerance max_error)
  string(JSON share GET "${manifest}" images ${index} tolerance max_share)
  set(golden_name "${name}" PARENT_SCOPE)
  set(golden_scene "${scene}" PARENT_SCOPE)
  set(golden_options "${options}" PARENT_SCOPE)
  set(golden_max_rmse "${rmse}" PARENT_SCOPE)
  set(golden_max_error "${error}" PARENT_SCOPE)
  set(golden_max_share "${share}" PARENT_SCOPE)
  set(golden_image "${image}" PARENT_SCOPE)
  set(golden_optimized_options "${optimized}" PARENT_SCOPE)
  set(golden_modes "${modes}" PARENT_SCOPE)
endfunction()
