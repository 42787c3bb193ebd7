# One ctest case per golden image and optimized traversal mode:
# golden_<name>_<mode> renders the manifest entry with the optimized engine
# and compares it with golden/<name>.exr under the entry's tolerances.
# Included by golden/CMakeLists.txt; the manifest is read with string(JSON).
set(RTT_GOLDEN_MODES mono packet omni frustum mft cone mft-cone)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/manifest.json)
file(READ ${CMAKE_CURRENT_LIST_DIR}/manifest.json rtt_golden_manifest)
string(JSON rtt_golden_count LENGTH "${rtt_golden_manifest}" images)
math(EXPR rtt_golden_last "${rtt_golden_count} - 1")
foreach(i RANGE ${rtt_golden_last})
  string(JSON name GET "${rtt_golden_manifest}" images ${i} name)
  string(JSON scene GET "${rtt_golden_manifest}" images ${i} scene)
  string(JSON options GET "${rtt_golden_manifest}" images ${i} options)
  string(JSON max_rmse GET "${rtt_golden_manifest}" images ${i} tolerance max_rmse)
  string(JSON max_error GET "${rtt_golden_manifest}" images ${i} tolerance max_error)
  string(JSON max_share GET "${rtt_golden_manifest}" images ${i} tolerance max_share)
  # optional fields: see manifest_list.cmake
  string(JSON golden ERROR_VARIABLE missing GET "${rtt_golden_manifest}" images ${i} golden)
  if(missing)
    set(golden ${name})
  endif()
  string(JSON optimized_options ERROR_VARIABLE missing GET "${rtt_golden_manifest}" images ${i} optimized_options)
  if(NOT missing)
    set(options "${optimized_options}")
  endif()
  string(JSON modes ERROR_VARIABLE missing GET "${rtt_golden_manifest}" images ${i} modes)
  if(missing)
    set(modes ${RTT_GOLDEN_MODES})
  else()
    separate_arguments(modes UNIX_COMMAND "${modes}")
  endif()
  foreach(mode ${modes})
    add_test(NAME golden_${name}_${mode}
             COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/check.sh $<TARGET_FILE:rtt> ${CMAKE_SOURCE_DIR} ${golden} ${scene}
                     "${options}" ${mode} ${max_rmse} ${max_error} ${max_share})
    set_tests_properties(golden_${name}_${mode} PROPERTIES TIMEOUT 120 LABELS "golden;conformance")
  endforeach()
endforeach()
