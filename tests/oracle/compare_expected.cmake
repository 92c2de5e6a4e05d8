# Re-runs the oracle on the corpus and compares with the committed expected.json.
execute_process(
  COMMAND ${PYTHON} ${SOURCE}/tests/oracle/photometric_oracle.py ${SOURCE}/tests/data/photometric
  OUTPUT_FILE ${OUT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the oracle failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}
  ${SOURCE}/tests/data/photometric/expected.json RESULT_VARIABLE diff)
if(NOT diff EQUAL 0)
  message(FATAL_ERROR "expected.json is not what the oracle computes now: regenerate it "
    "(tests/data/photometric/README.md) or find what changed")
endif()
