# The COST of each test (ctest's test property): the seconds it took in CI's sanitizer build (the
# plain build's own tests: there). A fresh ctest starts the costliest tests first, so that the
# run does not end on one long test while the other core waits. Pairs of name and seconds,
# written by scripts/update_test_costs.py from the record of a run; refresh them after adding or
# changing tests that take more than a few seconds.
set(DXLEMU_TEST_COSTS
)

# dxlemu_apply_test_costs(): gives every test of the current directory that the table names its
# COST (test properties can only be set where the test was added).
function(dxlemu_apply_test_costs)
  set(pairs ${DXLEMU_TEST_COSTS})
  list(LENGTH pairs length)
  if(length EQUAL 0)
    return()
  endif()
  math(EXPR last "${length} - 1")
  foreach(i RANGE 0 ${last} 2)
    math(EXPR j "${i} + 1")
    list(GET pairs ${i} name)
    list(GET pairs ${j} cost)
    if(TEST ${name})
      set_tests_properties(${name} PROPERTIES COST ${cost})
    endif()
  endforeach()
endfunction()
