# Project-wide compile options: warnings on everywhere, optional ASan+UBSan.
add_library(polarcam_options INTERFACE)
target_compile_options(polarcam_options INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Werror=return-type)
# GCC 12 reports false -Wrestrict warnings inside std::string's operator+ at -O2 (GCC bug 105329).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(polarcam_options INTERFACE -Wno-restrict)
endif()
if(POLARCAM_SANITIZE)
  target_compile_options(polarcam_options INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(polarcam_options INTERFACE -fsanitize=address,undefined)
  # Debian's Ceres is a static library built without sanitizers, with Eigen assuming malloc aligns to 16 bytes;
  # Eigen drops that assumption under ASan, and the two halves would then free each other's blocks with the wrong
  # function. glibc's and ASan's malloc both align to 16 bytes on 64-bit targets: keep the assumption everywhere.
  target_compile_definitions(polarcam_options INTERFACE EIGEN_MALLOC_ALREADY_ALIGNED=1)
endif()
if(POLARCAM_FUZZ)  # coverage for libFuzzer in every library; the harnesses link the fuzzer itself (fuzz/)
  target_compile_options(polarcam_options INTERFACE -fsanitize=fuzzer-no-link)
endif()
