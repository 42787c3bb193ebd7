# One ctest case per golden image and optimized traversal mode:
# golden_<name>_<mode> renders the manifest entry with the optimized engine
# and compares it with its golden image under the entry's tolerances.
# Included by golden/CMakeLists.txt; the manifest is read by manifest.cmake.
include(${CMAKE_CURRENT_LIST_DIR}/manifest.cmake)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/manifest.json)
file(READ ${CMAKE_CURRENT_LIST_DIR}/manifest.json rtt_golden_manifest)
string(JSON rtt_golden_count LENGTH "${rtt_golden_manifest}" images)
math(EXPR rtt_golden_last "${rtt_golden_count} - 1")
foreach(i RANGE ${rtt_golden_last})
  rtt_golden_entry("${rtt_golden_manifest}" ${i})
  foreach(mode ${golden_modes})
    add_test(NAME golden_${golden_name}_${mode}
             COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/check.sh $<TARGET_FILE:rtt> ${CMAKE_SOURCE_DIR} ${golden_image}
                     ${golden_scene} "${golden_optimized_options}" ${mode} ${golden_max_rmse} ${golden_max_error}
                     ${golden_max_share})
    set_tests_properties(golden_${golden_name}_${mode} PROPERTIES TIMEOUT 120 LABELS "golden;conformance")
  endforeach()
endforeach()
