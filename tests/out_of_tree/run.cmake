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
message(STATUS "out-of-tree controller built and ran against ${prefix}")
