#!/usr/bin/env bash
# CI's sanitizer stage (./build.sh sanitize; tests/sanitizers/README.md):
#  1. the whole test suite built with clang's AddressSanitizer +
#     UndefinedBehaviorSanitizer (+ float-cast-overflow), leak detection on;
#  2. the experiment loader's fuzzer for a fixed number of inputs, from the
#     examples and tests/fuzz/corpus (a crash fails the stage and is kept in
#     build-asan/fuzz_artifacts for tests/fuzz/regressions);
#  3. the multi-threaded tests (thread pool, determinism at 0, 1 and 2
#     threads) built with ThreadSanitizer.
# The Python module is left out of both builds: an instrumented extension
# cannot be loaded by Debian's uninstrumented python3.
# Build folders: build-asan, build-tsan (COLONY_ASAN_BUILD_DIR, COLONY_TSAN_BUILD_DIR).
# COLONY_FUZZ_RUNS sets the number of fuzz inputs (default 50000).
set -euo pipefail
cd "$(dirname "$0")/../.."
SRC=$PWD
ASAN_DIR=${COLONY_ASAN_BUILD_DIR:-build-asan}
TSAN_DIR=${COLONY_TSAN_BUILD_DIR:-build-tsan}
FUZZ_RUNS=${COLONY_FUZZ_RUNS:-50000}
SUPP=$SRC/tests/sanitizers

stage() { echo; echo "=== $* ($(date +%H:%M:%S))"; }
start=$SECONDS

stage "AddressSanitizer + UndefinedBehaviorSanitizer: build"
# -O1, as the sanitizers' authors advise: a third less compile time than -O2, and no frames inlined
# away from the reports.
SANITIZE_FLAGS=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -DNDEBUG")
CC=clang CXX=clang++ cmake -S . -B "$ASAN_DIR" "${SANITIZE_FLAGS[@]}" -DCOLONY_SANITIZE=address \
  -DCOLONY_BUILD_FUZZERS=ON -DCOLONY_BUILD_BENCHMARKS=OFF -DCOLONY_WITH_PYTHON=OFF
cmake --build "$ASAN_DIR" -j2

# intercept_tls_get_addr=0: clang 14's runtime takes some of glibc 2.36's dynamic TLS blocks for
# glibc 2.19's layout and LeakSanitizer's tracer then dies at exit ("Tracer caught signal 11"), at
# random, in processes that dlopen a library with thread-locals (the OSMesa plugin, with LLVM).
export ASAN_OPTIONS="detect_leaks=1:check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1:intercept_tls_get_addr=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$SUPP/ubsan.supp"
export LSAN_OPTIONS="suppressions=$SUPP/lsan.supp:print_suppressions=0"
stage "AddressSanitizer + UndefinedBehaviorSanitizer: every test"
# But the two out-of-tree tests: they install the build and compile controllers against it with the
# system compiler, uninstrumented; what they run of libcolony the other tests run too.
(cd "$ASAN_DIR" && ctest --output-on-failure -j2 --timeout 1200 -E '^(argos3_out_of_tree|out_of_tree_controller)$')

stage "Fuzzing the experiment loader: $FUZZ_RUNS inputs"
seeds=$ASAN_DIR/fuzz_seeds
work=$ASAN_DIR/fuzz_corpus
artifacts=$ASAN_DIR/fuzz_artifacts
rm -rf "$seeds" "$work" "$artifacts"
mkdir -p "$seeds" "$work" "$artifacts"
cp experiments/*.xml tests/fuzz/corpus/* "$seeds"/
if ! COLONY_PLUGIN_PATH=$ASAN_DIR/lib/colony "$ASAN_DIR/tests/loader_fuzzer" -seed=1 -runs="$FUZZ_RUNS" \
    -max_len=8192 -timeout=60 -rss_limit_mb=4096 -print_final_stats=1 -dict=tests/fuzz/loader.dict \
    -artifact_prefix="$artifacts/" "$work" "$seeds"; then
  echo "The fuzzer found a crash: $(ls "$artifacts")." >&2
  echo "Reproduce with $ASAN_DIR/tests/loader_fuzz_replay FILE; once fixed, add FILE to tests/fuzz/regressions." >&2
  exit 1
fi

stage "ThreadSanitizer: build the multi-threaded tests"
TSAN_TARGETS=(core_test kinematics2d_test dynamics2d_test dynamics3d_test media_sensors_test scenario_test
              swarm_experiments_test rope_launcher_test handbot_gripper_proximity_test light_scanner_battery_test
              manipulator_sensor_test handbot_shelf_test pointmass3d_test eyebot_dynamics3d_test eyebot_vision_test
              eyebot_guidance_test)
CC=clang CXX=clang++ cmake -S . -B "$TSAN_DIR" "${SANITIZE_FLAGS[@]}" -DCOLONY_SANITIZE=thread \
  -DCOLONY_BUILD_BENCHMARKS=OFF -DCOLONY_WITH_OSMESA=OFF -DCOLONY_WITH_PYTHON=OFF
cmake --build "$TSAN_DIR" -j2 --target "${TSAN_TARGETS[@]}"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$SUPP/tsan.supp"
stage "ThreadSanitizer: the multi-threaded tests"
(cd "$TSAN_DIR" && ctest --output-on-failure -j2 --timeout 1200 \
  -R 'ThreadCount|Threads|thread_pool|Determinism|Parallel')

stage "sanitizer stage passed in $((SECONDS - start)) s"
