# ViSP from Debian's component packages, contained to the targets that link it: the vpServo laws
# the control laws are checked against (cambio_control_visp_reference, for the tests and the
# benchmarks; control/CMakeLists.txt).
#
# Debian splits ViSP into per-module packages and ships no VISPConfig.cmake with them; and
# find_package(VISP) would anyway set CMAKE_CXX_STANDARD and add OpenMP flags to every target.
# So the three modules the servos' reference needs are found by hand and wrapped in
# cambio_link_visp(), which adds them PRIVATE to one target: its headers and flags reach nobody
# else. The libraries are linked by absolute path (not an imported target), as plain files.
set(CAMBIO_VISP_PACKAGES libvisp-vs-dev libvisp-visual-features-dev libvisp-core-dev)

find_path(CAMBIO_VISP_INCLUDE_DIR NAMES visp3/vs/vpServo.h
  DOC "Directory holding visp3/ (Debian: /usr/include/<multiarch>)")
find_library(CAMBIO_VISP_VS_LIBRARY NAMES visp_vs DOC "ViSP visual servoing module")
find_library(CAMBIO_VISP_VISUAL_FEATURES_LIBRARY NAMES visp_visual_features
  DOC "ViSP visual features module")
find_library(CAMBIO_VISP_CORE_LIBRARY NAMES visp_core DOC "ViSP core module")

set(_cambio_visp_missing "")
foreach(_var IN ITEMS CAMBIO_VISP_INCLUDE_DIR CAMBIO_VISP_VS_LIBRARY
                      CAMBIO_VISP_VISUAL_FEATURES_LIBRARY CAMBIO_VISP_CORE_LIBRARY)
  if(NOT ${_var})
    list(APPEND _cambio_visp_missing ${_var})
  endif()
endforeach()
if(_cambio_visp_missing)
  list(JOIN CAMBIO_VISP_PACKAGES " " _cambio_visp_list)
  message(FATAL_ERROR "ViSP not found (${_cambio_visp_missing}). Install Debian's component "
    "packages: sudo apt-get install ${_cambio_visp_list} (or run bash cmake/setup.sh build), "
    "or point CMAKE_PREFIX_PATH at a ViSP 3.x install.")
endif()
message(STATUS "ViSP: ${CAMBIO_VISP_INCLUDE_DIR}/visp3, ${CAMBIO_VISP_VS_LIBRARY}")

# Links the found ViSP modules PRIVATE into `target` (order: dependents first, core last).
function(cambio_link_visp target)
  target_include_directories(${target} SYSTEM PRIVATE ${CAMBIO_VISP_INCLUDE_DIR})
  target_link_libraries(${target} PRIVATE ${CAMBIO_VISP_VS_LIBRARY}
    ${CAMBIO_VISP_VISUAL_FEATURES_LIBRARY} ${CAMBIO_VISP_CORE_LIBRARY})
endfunction()
