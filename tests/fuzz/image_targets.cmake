# The image-reading fuzz target of `cambio perceive`, for tests/fuzz/CMakeLists.txt to include
# (include(${CMAKE_CURRENT_LIST_DIR}/image_targets.cmake)) in a clang build with libFuzzer.
# It adds the executable fuzz_image_read, built from the target and apps/outputs/image_{files,headers}.cpp, png_encoding.cpp (the
# program is one executable, not a library); -fsanitize=fuzzer is added here, ASan and UBSan come
# from the including build (CAMBIO_SANITIZE=ON, or the script's flags).
#   seed corpus: none needed; PNG, JPEG and PGM headers are found within seconds
#   run:         fuzz_image_read -max_len=65536 -rss_limit_mb=2048 -malloc_limit_mb=1024 CORPUS
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs)
add_executable(fuzz_image_read
  ${CMAKE_CURRENT_LIST_DIR}/fuzz_image_read.cpp
  ${CMAKE_CURRENT_LIST_DIR}/../../apps/outputs/image_files.cpp
  ${CMAKE_CURRENT_LIST_DIR}/../../apps/outputs/image_headers.cpp
  ${CMAKE_CURRENT_LIST_DIR}/../../apps/outputs/png_encoding.cpp)
cambio_set_target_options(fuzz_image_read)
target_include_directories(fuzz_image_read PRIVATE ${CMAKE_CURRENT_LIST_DIR}/../../apps/outputs)
target_compile_options(fuzz_image_read PRIVATE -fsanitize=fuzzer)
target_link_options(fuzz_image_read PRIVATE -fsanitize=fuzzer)
target_link_libraries(fuzz_image_read PRIVATE cambio::hal opencv_core opencv_imgproc
  opencv_imgcodecs)
