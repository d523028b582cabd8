# Installs Colony from BINARY_DIR into a temporary prefix, builds the
# out-of-tree controller against it, runs an experiment with the installed
# colony program and checks the robot stopped in front of the wall.
set(work ${BINARY_DIR}/out_of_tree)
file(REMOVE_RECURSE ${work})
set(prefix ${work}/install)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "failed (${status}): ${ARGN}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${prefix})
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/out_of_tree -B ${work}/build -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${work}/build -j2)
run(${prefix}/bin/colony run ${SOURCE_DIR}/tests/out_of_tree/forward_stop.xml --quiet
    --set controllers.forward_stop.library=${work}/build/libforward_stop.so --out ${work}/run)
file(READ ${work}/run/summary.json summary)
if(NOT summary MATCHES "\"ticks\": 200")
  message(FATAL_ERROR "unexpected summary: ${summary}")
endif()
# The installed program also finds installed plugins by name.
run(${prefix}/bin/colony query controller)
if(NOT last_output MATCHES "diffusion")
  message(FATAL_ERROR "installed colony does not list the installed diffusion controller:\n${last_output}")
endif()
# Its declared parameters, and a device's control interface, as the installed
# colony prints them.
run(${CMAKE_COMMAND} -E env COLONY_PLUGIN_PATH=${work}/build ${prefix}/bin/colony query forward_stop)
if(NOT last_output MATCHES "speed = a number in \\[0, 0.3\\] \\(m/s\\)  \\[default: 0.1\\]")
  message(FATAL_ERROR "colony query forward_stop does not list its parameter:\n${last_output}")
endif()
run(${prefix}/bin/colony query proximity)
if(NOT last_output MATCHES "header: #include \"sensors/proximity/proximity.h\"")
  message(FATAL_ERROR "colony query proximity does not name its header:\n${last_output}")
endif()
if(NOT EXISTS ${prefix}/include/colony/sensors/proximity/proximity.h)
  message(FATAL_ERROR "the header colony query names is not installed")
endif()
# The docs: README.md, docs/ and each device's and plugin's README, in the
# source tree's layout (share/doc/colony).
set(doc ${prefix}/share/doc/colony)
file(GLOB_RECURSE readmes RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/sensors/*/README.md
     ${SOURCE_DIR}/actuators/*/README.md ${SOURCE_DIR}/engines/*/README.md
     ${SOURCE_DIR}/entities/*/README.md ${SOURCE_DIR}/media/*/README.md
     ${SOURCE_DIR}/controllers/*/README.md ${SOURCE_DIR}/loop_functions/*/README.md
     ${SOURCE_DIR}/render/*/README.md ${SOURCE_DIR}/scripting/*/README.md)
file(GLOB docs RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/docs/*.md ${SOURCE_DIR}/docs/*.png)
list(LENGTH readmes count)
if(count LESS 40)
  message(FATAL_ERROR "only ${count} plugin READMEs found in ${SOURCE_DIR}")
endif()
foreach(file README.md ${docs} ${readmes})
  if(NOT EXISTS ${doc}/${file})
    message(FATAL_ERROR "cmake --install did not install ${file} as ${doc}/${file}")
  endif()
endforeach()
file(GLOB_RECURSE installed_docs ${doc}/*)
foreach(file ${installed_docs})
  if(NOT file MATCHES "\\.(md|png)$")
    message(FATAL_ERROR "${file} is installed with the docs but is not one")
  endif()
endforeach()
message(STATUS "out-of-tree controller built and ran against ${prefix}; docs in ${doc}")
