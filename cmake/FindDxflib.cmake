# dxflib (Debian: libdxflib-dev), which ships a pkg-config file but no CMake configuration.
# Defines the imported target Dxflib::dxflib.
find_package(PkgConfig REQUIRED)
pkg_check_modules(PC_DXFLIB QUIET IMPORTED_TARGET dxflib)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Dxflib REQUIRED_VARS PC_DXFLIB_FOUND PC_DXFLIB_LIBRARIES VERSION_VAR PC_DXFLIB_VERSION)
if(Dxflib_FOUND AND NOT TARGET Dxflib::dxflib)
  add_library(Dxflib::dxflib INTERFACE IMPORTED)
  target_link_libraries(Dxflib::dxflib INTERFACE PkgConfig::PC_DXFLIB)
endif()
