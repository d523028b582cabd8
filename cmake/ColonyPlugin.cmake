# colony_add_plugin(NAME SOURCES...)
# Builds a controller or loop-functions plugin: a shared library libNAME.so
# linked to libcolony. In the Colony build tree it goes to lib/colony, where
# the colony program finds it; out of tree it goes to the build folder and an
# experiment names it with library="path/to/libNAME.so".
function(colony_add_plugin name)
  add_library(${name} MODULE ${ARGN})
  if(TARGET Colony::colony)
    target_link_libraries(${name} PRIVATE Colony::colony)
  else()
    target_link_libraries(${name} PRIVATE colony)
    set_target_properties(${name} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${COLONY_PLUGIN_OUTPUT_DIR})
    install(TARGETS ${name} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/colony)
    set_property(GLOBAL APPEND PROPERTY COLONY_PLUGIN_TARGETS ${name})
  endif()
  set_target_properties(${name} PROPERTIES PREFIX "lib" CXX_VISIBILITY_PRESET default)
endfunction()
