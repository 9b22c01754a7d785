# Run by ctest: install, configure the consumer against the prefix, build it, run it.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result}):\n${out}\n${err}")
  endif()
endfunction()

run_step("install" ${CMAKE_COMMAND} --install ${CAMBIO_BINARY_DIR} --prefix ${prefix})
run_step("configure consumer" ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${WORK_DIR}/build
         -DCMAKE_PREFIX_PATH=${prefix})
run_step("build consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run_step("run consumer" ${WORK_DIR}/build/cambio_consumer
         ${prefix}/share/cambio/firmware_config/experiments/vergence_sphere.yaml)
if(NOT EXISTS ${prefix}/bin/cambio)
  message(FATAL_ERROR "the install prefix has no bin/cambio")
endif()
if(NOT EXISTS ${prefix}/share/cambio/firmware_config/rigs/cambio.yaml)
  message(FATAL_ERROR "the install prefix lacks the shipped rig files")
endif()
