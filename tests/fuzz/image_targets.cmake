# The image-reading fuzz target of `cambio perceive`, for tests/fuzz/CMakeLists.txt to include
# (include(${CMAKE_CURRENT_LIST_DIR}/image_targets.cmake)) in a clang build with libFuzzer.
# It adds the executable fuzz_image_read, built from the target and the image sources of
# apps/outputs (the PNG, JPEG and PGM/PPM decoders over libpng and libjpeg are fuzzed with it; the
# program is one executable, not a library); -fsanitize=fuzzer is added here, ASan and UBSan come
# from the including build (CAMBIO_SANITIZE=ON, or the script's flags).
#   seed corpus: tests/fuzz/seeds/image_read/ (small files of each kind the decoders take:
#                palette, interlaced, 16-bit and alpha PNGs, progressive and EXIF JPEGs, PGM/PPM)
#   run:         fuzz_image_read -max_len=65536 -rss_limit_mb=2048 -malloc_limit_mb=1024 CORPUS
find_package(PNG REQUIRED)
find_package(JPEG REQUIRED)
set(_cambio_image_sources exif_orientation image_files image_headers jpeg_decoding png_decoding
  png_encoding pnm_decoding)
list(TRANSFORM _cambio_image_sources PREPEND ${CMAKE_CURRENT_LIST_DIR}/../../apps/outputs/)
list(TRANSFORM _cambio_image_sources APPEND .cpp)
add_executable(fuzz_image_read ${CMAKE_CURRENT_LIST_DIR}/fuzz_image_read.cpp ${_cambio_image_sources})
cambio_set_target_options(fuzz_image_read)
target_include_directories(fuzz_image_read PRIVATE ${CMAKE_CURRENT_LIST_DIR}/../../apps/outputs)
target_compile_options(fuzz_image_read PRIVATE -fsanitize=fuzzer)
target_link_options(fuzz_image_read PRIVATE -fsanitize=fuzzer)
target_link_libraries(fuzz_image_read PRIVATE cambio::hal PNG::PNG JPEG::JPEG)
