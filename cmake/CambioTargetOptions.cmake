# Per-target compile settings. Using target properties keeps them immune to packages (ViSP) that
# rewrite CMAKE_CXX_STANDARD or CMAKE_CXX_FLAGS.
function(cambio_set_target_options target)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF POSITION_INDEPENDENT_CODE ON)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor)
  # GCC 12 reports a false -Wrestrict inside libstdc++'s string operator+ when inlining under
  # -fsanitize (GCC PR 105651, fixed in 13); it is never about our code.
  target_compile_options(${target} PRIVATE
    $<$<AND:$<CXX_COMPILER_ID:GNU>,$<VERSION_LESS:$<CXX_COMPILER_VERSION>,13>>:-Wno-restrict>)
  if(CAMBIO_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(CAMBIO_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
                                             -fno-sanitize-recover=undefined)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
  get_target_property(type ${target} TYPE)
  if(CAMBIO_SANITIZE AND type STREQUAL "EXECUTABLE")
    # AddressSanitizer's metadata makes a position-independent program carry millions of
    # relocations (3.2 million in `cambio`), applied at every start: 0.24 s of each of the
    # processes the tests start. A fixed-address program has none.
    target_link_options(${target} PRIVATE -no-pie)
  endif()
endfunction()

# A library of this project: cambio_<name> with the alias cambio::<name>; its public headers are
# the folder's include/ (as <cambio/<name>/...>), in the build tree and in an install.
function(cambio_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  add_library(cambio_${name} ${ARG_SOURCES})
  add_library(cambio::${name} ALIAS cambio_${name})
  set_target_properties(cambio_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME cambio_${name})
  cambio_set_target_options(cambio_${name})
  target_include_directories(cambio_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
endfunction()
