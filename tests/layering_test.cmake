# The layering rules of docs/architecture.md, checked on the include graph and the sources:
#  - control/ and perception/ see the HAL only: nothing from sim/ or drivers/;
#  - hal/ depends on Eigen and the standard library alone, and names nothing of the config layer
#    (not even a forward declaration): backends get the HAL's HardwareInfo;
#  - control/ (the runtime included) never includes cambio/config/: the application maps
#    configuration onto controller and schedule parameters.
set(violations "")

file(GLOB_RECURSE upper_files ${SOURCE_DIR}/control/*.hpp ${SOURCE_DIR}/control/*.cpp
     ${SOURCE_DIR}/perception/*.hpp ${SOURCE_DIR}/perception/*.cpp)
foreach(path IN LISTS upper_files)
  file(STRINGS ${path} includes REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]")
  foreach(line IN LISTS includes)
    if(line MATCHES "[<\"](cambio/)?(sim|drivers)/" OR line MATCHES "mujoco" OR line MATCHES "linux/can")
      list(APPEND violations "${path}: ${line}")
    elseif(path MATCHES "/control/" AND line MATCHES "[<\"]cambio/config/")
      list(APPEND violations "${path}: ${line} (control/ does not depend on firmware_config/)")
    endif()
  endforeach()
endforeach()

file(GLOB_RECURSE hal_files ${SOURCE_DIR}/hal/*.hpp ${SOURCE_DIR}/hal/*.cpp)
foreach(path IN LISTS hal_files)
  file(STRINGS ${path} includes REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]")
  foreach(line IN LISTS includes)
    if(line MATCHES "[<\"]cambio/" AND NOT line MATCHES "[<\"]cambio/hal/")
      list(APPEND violations "${path}: ${line} (the HAL may include only cambio/hal/)")
    elseif(line MATCHES "[<\"](yaml-cpp|opencv2|mujoco|EGL|GL|visp)")
      list(APPEND violations "${path}: ${line} (the HAL depends on Eigen alone)")
    endif()
  endforeach()
  file(STRINGS ${path} config_names REGEX "(cambio::)?config::|namespace cambio::config")
  foreach(line IN LISTS config_names)
    list(APPEND violations "${path}: ${line} (the HAL names nothing of firmware_config/)")
  endforeach()
endforeach()

# The config layer depends on no driver and no simulator: backends check their own settings.
file(GLOB_RECURSE config_files ${SOURCE_DIR}/firmware_config/*.hpp ${SOURCE_DIR}/firmware_config/*.cpp
     ${SOURCE_DIR}/firmware_config/CMakeLists.txt)
foreach(path IN LISTS config_files)
  file(STRINGS ${path} uses REGEX
       "[<\"]cambio/(can|canopen|sim|virtual_rig)/|cambio::(can|canopen|sim|virtual_rig)[ )]|cambio::(can|canopen|sim|virtual_rig)$")
  foreach(line IN LISTS uses)
    list(APPEND violations "${path}: ${line} (firmware_config/ depends on no driver or simulator)")
  endforeach()
endforeach()

# Backends are found by what they offer, never by name and cast: outside tests no source casts
# down to a backend, executor or device type, nor uses dynamic_cast; the layers above the
# backends (apps/, control/, perception/, hal/) never spell a backend's name (they use the
# backend's own constant where a command is about one backend).
file(GLOB_RECURSE all_sources ${SOURCE_DIR}/apps/*.cpp ${SOURCE_DIR}/apps/*.hpp
     ${SOURCE_DIR}/control/*.cpp ${SOURCE_DIR}/control/*.hpp
     ${SOURCE_DIR}/perception/*.cpp ${SOURCE_DIR}/perception/*.hpp
     ${SOURCE_DIR}/hal/*.cpp ${SOURCE_DIR}/hal/*.hpp
     ${SOURCE_DIR}/sim/*.cpp ${SOURCE_DIR}/sim/*.hpp
     ${SOURCE_DIR}/drivers/*.cpp ${SOURCE_DIR}/drivers/*.hpp
     ${SOURCE_DIR}/firmware_config/*.cpp ${SOURCE_DIR}/firmware_config/*.hpp)
foreach(path IN LISTS all_sources)
  file(STRINGS ${path} casts REGEX
       "dynamic_cast|static_cast<[^>]*(Backend|Executor|JointGroup|Camera|TouchSensor|CanBus)[ ]*[&*]")
  foreach(line IN LISTS casts)
    list(APPEND violations "${path}: ${line} (ask hal::BackendOffers by type, do not cast)")
  endforeach()
  if(path MATCHES "/(apps|control|perception|hal)/" AND NOT path MATCHES "/builtin_backends\\.")
    file(STRINGS ${path} names REGEX "\"(sim|socketcan|v4l2)\"")
    foreach(line IN LISTS names)
      list(APPEND violations "${path}: ${line} (a backend's name belongs to its registration)")
    endforeach()
  endif()
endforeach()

list(LENGTH upper_files upper_count)
list(LENGTH hal_files hal_count)
if(upper_count EQUAL 0 OR hal_count EQUAL 0)
  message(FATAL_ERROR "layering test found no sources under ${SOURCE_DIR}")
endif()
if(violations)
  list(JOIN violations "\n  " text)
  message(FATAL_ERROR "layering violations:\n  ${text}")
endif()
message(STATUS "layering: ${upper_count} control/perception files and ${hal_count} HAL files clean")
