# Installs Colony from BINARY_DIR into a temporary prefix, builds the
# ARGoS-style controllers and loop functions of this folder against it with
# find_package(Colony), runs each experiment (ARGoS's file layout) with the
# installed colony program from the folder holding build/ (as ARGoS users run
# theirs), and checks what a user would see. The loop functions write their
# figures, "name value" per line, into that folder, as ARGoS loop functions
# do.
set(work ${BINARY_DIR}/argos3_out_of_tree)
file(REMOVE_RECURSE ${work})
file(MAKE_DIRECTORY ${work})
set(prefix ${work}/install)
set(here ${SOURCE_DIR}/tests/argos3_out_of_tree)

# Runs a command in ${work}; fails unless it exits with `expected`.
function(run_expecting expected)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY ${work} RESULT_VARIABLE status
                  OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL expected)
    message(FATAL_ERROR "exit status ${status}, expected ${expected}: ${ARGN}\n${out}\n${err}")
  endif()
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()

# Reads "name value" lines of `file` into variables <prefix>_<name>.
function(read_figures file prefix)
  file(STRINGS ${file} lines)
  foreach(line ${lines})
    if(line MATCHES "^([a-z_]+) (.+)$")
      set(${prefix}_${CMAKE_MATCH_1} ${CMAKE_MATCH_2} PARENT_SCOPE)
    endif()
  endforeach()
endfunction()

macro(expect message)
  if(NOT (${ARGN}))
    message(FATAL_ERROR "${message}")
  endif()
endmacro()

# "hash" of a run's summary.json.
function(final_hash run out)
  file(READ ${run}/summary.json summary)
  string(REGEX MATCH "\"final_state_hash\": \"([0-9a-f]+)\"" _ "${summary}")
  set(${out} ${CMAKE_MATCH_1} PARENT_SCOPE)
endfunction()

run_expecting(0 ${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${prefix})
run_expecting(0 ${CMAKE_COMMAND} -S ${here} -B ${work}/build -DCMAKE_BUILD_TYPE=Release
              -DCMAKE_PREFIX_PATH=${prefix})
run_expecting(0 ${CMAKE_COMMAND} --build ${work}/build -j2)
set(colony ${prefix}/bin/colony)

# Diffusion: no robot ever touches a wall, and the swarm spreads out.
run_expecting(0 ${colony} run ${here}/experiments/diffusion.argos --quiet --out ${work}/diffusion)
read_figures(${work}/diffusion.txt d)
message(STATUS "diffusion: closest to a wall ${d_min_wall_clearance} m, closest robots "
               "${d_min_robot_gap} m apart, spread ${d_initial_dispersion} -> "
               "${d_final_dispersion} m")
expect("a robot touched a wall (clearance ${d_min_wall_clearance} m)"
       d_min_wall_clearance GREATER 0.005)
expect("the swarm did not spread out (x${d_dispersion_growth})" d_dispersion_growth GREATER 2)
# velocity="5" in the file is ARGoS's cm/s: the robots drive at 5 cm/s, not
# 5 m/s (nor the marXbot's 0.3 m/s limit).
expect("the fastest robot moved at ${d_max_speed} m/s, not 0.05" d_max_speed GREATER 0.045)
expect("the fastest robot moved at ${d_max_speed} m/s, not 0.05" d_max_speed LESS 0.0505)

# Flocking over range-and-bearing: headings align, every robot hears
# neighbours (LEDs green), the flock stays together and moves.
run_expecting(0 ${colony} run ${here}/experiments/flocking.argos --quiet --out ${work}/flocking)
read_figures(${work}/flocking.txt f)
message(STATUS "flocking: polarization ${f_initial_polarization} -> ${f_final_polarization}, "
               "${f_green} of ${f_robots} green, farthest ${f_farthest_from_centre} m from the "
               "centre, which moved ${f_centre_travelled} m")
expect("headings did not start scattered" f_initial_polarization LESS 0.6)
expect("headings did not align (${f_final_polarization})" f_final_polarization GREATER 0.95)
expect("${f_green} of ${f_robots} robots hear neighbours" f_green EQUAL f_robots)
expect("the flock broke up" f_farthest_from_centre LESS 1.5)
expect("the flock did not move" f_centre_travelled GREATER 1)

# Synchronization with the camera and LEDs: flashes converge onto the same
# ticks, and every robot still flashes.
run_expecting(0 ${colony} run ${here}/experiments/synchronization.argos --quiet
              --out ${work}/synchronization)
read_figures(${work}/synchronization.txt s)
message(STATUS "synchronization: flashes on ${s_first_period_flash_ticks} distinct ticks in the "
               "first period, ${s_last_period_flash_ticks} in the last "
               "(${s_robots_flashing_last_period} robots)")
expect("flashes did not start out of step" s_first_period_flash_ticks GREATER_EQUAL 8)
expect("flashes did not converge" s_last_period_flash_ticks LESS_EQUAL 3)
expect("not every robot flashes" s_robots_flashing_last_period EQUAL 16)

# Foraging, controller side: items come back to the nest, the robots' own
# counts (read by the loop functions through GetController) agree, and
# returning robots find the nest by its grey floor (which the loop functions
# paint) and rest there.
run_expecting(0 ${colony} run ${here}/experiments/foraging.argos --quiet --out ${work}/foraging)
read_figures(${work}/foraging_summary.txt g)
message(STATUS "foraging: ${g_collected} items collected, ${g_counted_by_robots} by the robots' "
               "count; robots came to rest in the nest ${g_arrivals_in_nest} times")
expect("too few items collected (${g_collected})" g_collected GREATER_EQUAL 5)
expect("robots counted ${g_counted_by_robots}, loop functions ${g_collected}"
       g_counted_by_robots EQUAL g_collected)
expect("returning robots never found the nest" g_arrivals_in_nest GREATER_EQUAL 3)
# The same run on 2 threads: ARGoS controllers draw from their robots' own
# random streams, so the result is the same.
run_expecting(0 ${colony} run ${here}/experiments/foraging.argos --quiet --threads 2
              --out ${work}/foraging-2threads)
final_hash(${work}/foraging one_thread)
final_hash(${work}/foraging-2threads two_threads)
expect("foraging differs on 2 threads: ${one_thread} vs ${two_threads}"
       one_thread STREQUAL two_threads)

# A malformed parameter stops the run before it starts, naming the file,
# line, parameter and value.
run_expecting(2 ${colony} run ${here}/experiments/bad_parameter.argos --quiet
              --out ${work}/bad_parameter)
foreach(part "bad_parameter.argos:" "flocking.gain" "strong" "a finite number")
  string(FIND "${last_output}" "${part}" at)
  expect("the error does not name '${part}':\n${last_output}" NOT at EQUAL -1)
endforeach()

message(STATUS "ARGoS-style controllers and loop functions built against ${prefix} and ran")
