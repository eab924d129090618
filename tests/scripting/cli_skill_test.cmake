# Runs `marvin skill test DIR` and checks its summary line and exit code.
#   cmake -DMARVIN=<marvin> -DDIR=<skill> -DSUMMARY="N passed, M failed" -DEXIT=<0|1> -P cli_skill_test.cmake
execute_process(COMMAND ${MARVIN} skill test ${DIR} RESULT_VARIABLE code OUTPUT_VARIABLE out
                ERROR_VARIABLE err)
if(NOT out MATCHES "${SUMMARY}")
  message(FATAL_ERROR "expected \"${SUMMARY}\" in the output of marvin skill test ${DIR}:\n${out}${err}")
endif()
if(NOT code EQUAL EXIT)
  message(FATAL_ERROR "marvin skill test ${DIR} exited with ${code}, expected ${EXIT}:\n${out}${err}")
endif()
