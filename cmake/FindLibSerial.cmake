# libserial (Debian: libserial-dev) ships a pkg-config file but no CMake config. Defines LibSerial::LibSerial.
find_package(PkgConfig REQUIRED)
pkg_check_modules(PC_LIBSERIAL QUIET IMPORTED_TARGET libserial)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(LibSerial REQUIRED_VARS PC_LIBSERIAL_FOUND PC_LIBSERIAL_LIBRARIES VERSION_VAR PC_LIBSERIAL_VERSION)
if(LibSerial_FOUND AND NOT TARGET LibSerial::LibSerial)
  add_library(LibSerial::LibSerial INTERFACE IMPORTED)
  target_link_libraries(LibSerial::LibSerial INTERFACE PkgConfig::PC_LIBSERIAL)
endif()
