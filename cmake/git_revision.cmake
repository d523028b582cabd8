# Run at every build (cmake -P): writes OUT, a header that defines
# COLONY_GIT_REVISION as the commit the checkout at SOURCE_DIR is on, with
# "-dirty" when tracked files differ from it, or "unknown" when git cannot
# tell. The file is rewritten only when that changes, so only the one source
# that includes it recompiles, and only then.
cmake_minimum_required(VERSION 3.18)
set(revision "unknown")
execute_process(COMMAND ${GIT} rev-parse HEAD
                WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE head OUTPUT_STRIP_TRAILING_WHITESPACE
                RESULT_VARIABLE status ERROR_QUIET)
if(status EQUAL 0 AND head)
  set(revision ${head})
  execute_process(COMMAND ${GIT} status --porcelain --untracked-files=no
                  WORKING_DIRECTORY ${SOURCE_DIR}
                  OUTPUT_VARIABLE changes RESULT_VARIABLE status ERROR_QUIET)
  if(NOT status EQUAL 0)
    set(revision "unknown")
  elseif(changes)
    string(APPEND revision "-dirty")
  endif()
endif()
file(CONFIGURE OUTPUT ${OUT}
     CONTENT "#define COLONY_GIT_REVISION \"@revision@\"\n" @ONLY)
