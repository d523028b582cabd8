# Sanitizer and fuzzer builds (CI's sanitizer stage, ./build.sh sanitize).
#
#   -DCOLONY_SANITIZE=address   AddressSanitizer + UndefinedBehaviorSanitizer
#                               (+ float-cast-overflow), every finding fatal
#   -DCOLONY_SANITIZE=thread    ThreadSanitizer
#   -DCOLONY_BUILD_FUZZERS=ON   the libFuzzer targets (clang only); the whole
#                               build is instrumented for coverage
#
# Run the tests of such a build with the options in tests/sanitizers/README.md.
set(COLONY_SANITIZE "" CACHE STRING "Build with sanitizers: address (ASan+UBSan) or thread (TSan)")
set_property(CACHE COLONY_SANITIZE PROPERTY STRINGS "" address thread)
option(COLONY_BUILD_FUZZERS "Build the libFuzzer targets (needs clang)" OFF)

if(COLONY_SANITIZE STREQUAL "address")
  set(colony_sanitize_flags -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all
                            -fno-omit-frame-pointer)
elseif(COLONY_SANITIZE STREQUAL "thread")
  set(colony_sanitize_flags -fsanitize=thread -fno-omit-frame-pointer)
elseif(NOT COLONY_SANITIZE STREQUAL "")
  message(FATAL_ERROR "COLONY_SANITIZE=${COLONY_SANITIZE}: expected address, thread or nothing")
endif()
if(colony_sanitize_flags)
  add_compile_options(${colony_sanitize_flags})
  add_link_options(${colony_sanitize_flags})
  # Sanitized code is slow; keep some optimisation but full stacks. Line
  # tables are all a sanitizer's stack trace needs (file:line per frame);
  # full debug info costs compile and link time for nothing here.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    add_compile_options(-gline-tables-only)
  else()
    add_compile_options(-g1)
  endif()
endif()

if(COLONY_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "COLONY_BUILD_FUZZERS needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++")
  endif()
  # Coverage instrumentation everywhere; the fuzzer's own main only in the
  # fuzz targets (tests/fuzz).
  add_compile_options(-fsanitize=fuzzer-no-link)
  add_link_options(-fsanitize=fuzzer-no-link)
endif()
