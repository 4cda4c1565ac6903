# Runs one fuzz target for a fixed number of runs from a fresh work directory; fails on any crash,
# sanitizer report or broken invariant (libFuzzer then exits non-zero and leaves the input in
# WORK_DIR/artifacts). Called by ctest with -DFUZZER, -DSEED_CORPUS, -DWORK_DIR and -DRUNS, and
# optionally -DMAX_LEN (default 4096) and -DEXTRA_CORPUS (a second seed directory).

foreach(var FUZZER SEED_CORPUS WORK_DIR RUNS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_smoke.cmake needs -D${var}=...")
  endif()
endforeach()

if(NOT DEFINED MAX_LEN)
  # The largest packet the 2.0 framer accepts.
  set(MAX_LEN 4096)
endif()

set(corpora ${SEED_CORPUS})
if(DEFINED EXTRA_CORPUS)
  list(APPEND corpora ${EXTRA_CORPUS})
endif()

file(GLOB seeds ${SEED_CORPUS}/*)
if(NOT seeds)
  message(FATAL_ERROR "no seed corpus in ${SEED_CORPUS}: build first (ninja builds it)")
endif()

# A fresh directory each time, so that a run does not depend on what earlier runs found.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/corpus ${WORK_DIR}/artifacts)

# -seed=1 makes the run repeatable.
execute_process(
  COMMAND ${FUZZER} -runs=${RUNS} -seed=1 -max_len=${MAX_LEN} -print_final_stats=1
          -artifact_prefix=${WORK_DIR}/artifacts/ ${WORK_DIR}/corpus ${corpora}
  WORKING_DIRECTORY ${WORK_DIR}
  RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${FUZZER} failed (${result}); the input is in ${WORK_DIR}/artifacts")
endif()
