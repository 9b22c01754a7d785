# Included by the top-level CMakeLists.txt when CAMBIO_FUZZ is on, before any library is defined:
# clang's libFuzzer with AddressSanitizer and UndefinedBehaviorSanitizer (README.md).
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "CAMBIO_FUZZ needs clang's libFuzzer: configure with "
                      "-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ "
                      "(tests/fuzz/run_fuzzers.sh does)")
endif()

# Every library is compiled with libFuzzer's coverage instrumentation (without its main) and the
# sanitizers that turn a memory error or undefined behaviour into a crash.
add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
                    -fno-omit-frame-pointer)
add_link_options(-fsanitize=address,undefined)

# Everything cambio_add_fuzzer() defines; run_fuzzers.sh builds this target and runs every
# bin/fuzz_* it finds.
add_custom_target(fuzzers)

# cambio_add_fuzzer(fuzz_<name> SOURCES ... LIBS ...): a libFuzzer executable (its sources define
# LLVMFuzzerTestOneInput), part of the `fuzzers` target. Callable from any folder's CMakeLists.
function(cambio_add_fuzzer name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  if(NOT name MATCHES "^fuzz_")
    message(FATAL_ERROR "cambio_add_fuzzer: '${name}' must be named fuzz_<name> "
                        "(run_fuzzers.sh runs bin/fuzz_*)")
  endif()
  add_executable(${name} ${ARG_SOURCES})
  cambio_set_target_options(${name})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS})
  target_link_options(${name} PRIVATE -fsanitize=fuzzer)
  add_dependencies(fuzzers ${name})
endfunction()
