# Project-wide compile options: warnings on everywhere, optional ASan+UBSan.
add_library(polarcam_options INTERFACE)
target_compile_options(polarcam_options INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Werror=return-type)
# GCC 12 reports false -Wrestrict, -Warray-bounds, -Wstringop-overflow and -Wstringop-overread warnings inside
# std::string's operator+ and copies once it inlines them (GCC bug 105329 and its family, fixed in GCC 13).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(polarcam_options INTERFACE -Wno-restrict -Wno-array-bounds -Wno-stringop-overflow
    -Wno-stringop-overread)
endif()
if(POLARCAM_SANITIZE)
  target_compile_options(polarcam_options INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(polarcam_options INTERFACE -fsanitize=address,undefined)
  # Debian's Ceres is a static library built without sanitizers, with Eigen assuming malloc aligns to 16 bytes;
  # Eigen drops that assumption under ASan, and the two halves would then free each other's blocks with the wrong
  # function. glibc's and ASan's malloc both align to 16 bytes on 64-bit targets: keep the assumption everywhere.
  target_compile_definitions(polarcam_options INTERFACE EIGEN_MALLOC_ALREADY_ALIGNED=1)
endif()

# polarcam_light_code(TARGET [INTERFACE]): the optimisation of code that is not hot: the command files (they parse
# arguments and format output) and the test programs' own code. The libraries keep the build's optimisation, so
# the tests exercise the code users run. At -O3 a command or test file spends most of its compile time generating
# CLI11's, nlohmann-json's and GoogleTest's inline code: Release compiles these files at -O1 (about 40 % less
# compile time); the sanitized build at -O0 (a third of its -O1 time).
function(polarcam_light_code target)
  set(scope PRIVATE)
  if(ARGN)
    set(scope ${ARGN})
  endif()
  if(POLARCAM_SANITIZE)
    target_compile_options(${target} ${scope} -O0)
  else()
    target_compile_options(${target} ${scope} $<$<CONFIG:Release>:-O1>)
  endif()
endfunction()
