# Project-wide compile options: warnings on everywhere, optional ASan+UBSan.
add_library(polarcam_options INTERFACE)
target_compile_options(polarcam_options INTERFACE -Wall -Wextra -Wpedantic -Wshadow)
if(POLARCAM_SANITIZE)
  target_compile_options(polarcam_options INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(polarcam_options INTERFACE -fsanitize=address,undefined)
endif()
