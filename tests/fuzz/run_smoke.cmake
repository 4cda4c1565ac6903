# Runs one fuzz target from a fresh work directory: every hand-written or generated seed, a fixed
# sample of what long runs found, then a bounded number of mutations. Fails on any crash,
# sanitizer report or broken invariant (libFuzzer then exits non-zero and leaves the input in
# WORK_DIR/artifacts). Called by ctest with -DFUZZER, -DSEED_CORPUS, -DWORK_DIR, -DFOUND and
# -DNEW_RUNS, and optionally -DMAX_LEN (default 4096) and -DEXTRA_CORPUS (a second seed directory).
#
# Long runs' finds are the files named by their SHA-1 (40 hex digits); there are thousands, and
# replaying them all made each smoke run grow with every long run merged. FOUND of them are
# replayed, the same ones every time: those whose SHA-1 of "smoke/NAME" sorts first. The long runs
# replay the whole corpus (docs/reliability.md).

foreach(var FUZZER SEED_CORPUS WORK_DIR FOUND NEW_RUNS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_smoke.cmake needs -D${var}=...")
  endif()
endforeach()

if(NOT DEFINED MAX_LEN)
  # The largest packet the 2.0 framer accepts.
  set(MAX_LEN 4096)
endif()

file(GLOB generated ${SEED_CORPUS}/*)
if(NOT generated)
  message(FATAL_ERROR "no seed corpus in ${SEED_CORPUS}: build first (ninja builds it)")
endif()
set(all ${generated})
if(DEFINED EXTRA_CORPUS)
  file(GLOB extra ${EXTRA_CORPUS}/*)
  list(APPEND all ${extra})
endif()

set(seeds)
set(found)
foreach(path ${all})
  get_filename_component(name ${path} NAME)
  string(LENGTH "${name}" length)
  if(name MATCHES "^[0-9a-f]+$" AND length EQUAL 40)
    string(SHA1 key "smoke/${name}")
    list(APPEND found "${key}|${path}")
  else()
    list(APPEND seeds ${path})
  endif()
endforeach()
list(SORT found)
list(LENGTH found found_count)
list(SUBLIST found 0 ${FOUND} found)
foreach(entry ${found})
  string(REGEX REPLACE "^[0-9a-f]+\\|" "" path ${entry})
  list(APPEND seeds ${path})
endforeach()

# A fresh directory each time, so that a run does not depend on what earlier runs found. The
# chosen seeds are copied into it: libFuzzer takes directories, and writes what it finds to the
# first one it is given.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/corpus ${WORK_DIR}/seeds ${WORK_DIR}/artifacts)
set(index 0)
foreach(path ${seeds})
  get_filename_component(name ${path} NAME)
  # Generated and committed seeds may share a name: the index keeps both.
  file(COPY_FILE ${path} ${WORK_DIR}/seeds/${index}-${name})
  math(EXPR index "${index} + 1")
endforeach()
list(LENGTH seeds seed_count)

# libFuzzer counts the seeds' executions in -runs. -seed=1 makes the run repeatable.
math(EXPR runs "${seed_count} + ${NEW_RUNS}")
list(LENGTH found replayed)
message(STATUS "${seed_count} seeds (${replayed} of ${found_count} long-run finds), "
               "then ${NEW_RUNS} new inputs")
execute_process(
  COMMAND ${FUZZER} -runs=${runs} -seed=1 -max_len=${MAX_LEN} -print_final_stats=1
          -artifact_prefix=${WORK_DIR}/artifacts/ ${WORK_DIR}/corpus ${WORK_DIR}/seeds
  WORKING_DIRECTORY ${WORK_DIR}
  RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${FUZZER} failed (${result}); the input is in ${WORK_DIR}/artifacts")
endif()
