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

# The outside project's behaviour plugin, run by the installed program from an experiment file
# written here that names it, on the installed rig and scene.
# (Script mode knows no CMAKE_SHARED_MODULE_SUFFIX: the project is Linux only.)
set(plugin ${WORK_DIR}/build/libconsumer_behaviour.so)
if(NOT EXISTS ${plugin})
  message(FATAL_ERROR "the consumer built no behaviour plugin at ${plugin}")
endif()
set(config ${prefix}/share/cambio/firmware_config)
file(WRITE ${WORK_DIR}/sweep.yaml
"experiment:
  name: consumer_sweep
  rig: ${config}/rigs/cambio.yaml
  scene: ${config}/scenes/attention_scan.yaml
  perception: ${config}/perception/vergence.yaml
  executor: lockstep
  duration_s: 1.0
  task: gaze
  behaviour:
    name: sweep
    rate_hz: 10
    plugins: [build/libconsumer_behaviour.so]
    params: {amplitude_deg: 4, period_s: 0.3}
")
run_step("run the consumer's behaviour" ${prefix}/bin/cambio run ${WORK_DIR}/sweep.yaml
         --out ${WORK_DIR}/sweep_out)
file(READ ${WORK_DIR}/sweep_out/summary.json summary)
string(JSON behaviour_name GET "${summary}" behaviour name)
string(JSON behaviour_status GET "${summary}" behaviour status)
string(JSON behaviour_failed GET "${summary}" behaviour failed)
string(JSON behaviour_plugin GET "${summary}" behaviour plugins 0)
if(NOT behaviour_name STREQUAL "sweep" OR behaviour_failed OR
   NOT behaviour_status MATCHES "^sweep: [1-9][0-9]* saccades, [1-9][0-9]* feature maps seen$" OR
   NOT behaviour_plugin STREQUAL plugin)
  message(FATAL_ERROR "the plugin's behaviour did not run as expected: name '${behaviour_name}', "
    "status '${behaviour_status}', failed ${behaviour_failed}, plugin '${behaviour_plugin}'")
endif()

# The outside project's compile lines: nothing of ViSP, and never C++17 (what the servos' ViSP
# reference, a target of the tests alone, is compiled as) leaks through the installed targets.
file(READ ${WORK_DIR}/build/compile_commands.json compile_commands)
if(compile_commands MATCHES "[Vv][Ii][Ss][Pp]" OR compile_commands MATCHES "-std=(c|gnu)\\+\\+17")
  message(FATAL_ERROR "the consumer's compile lines carry ViSP or C++17 flags:\n${compile_commands}")
endif()
if(NOT compile_commands MATCHES "sweep_behaviour.cpp")
  message(FATAL_ERROR "the consumer's compile lines lack the plugin's source")
endif()
