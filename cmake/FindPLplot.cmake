# PLplot (Debian: libplplot-dev, plplot-driver-cairo). Debian's plplotConfig.cmake refers to the bindings of
# every language (Tcl, Qt, wxWidgets...) and fails without them, so this module asks pkg-config for the C++
# library only. Defines the imported target PLplot::plplotcxx.
find_package(PkgConfig REQUIRED)
pkg_check_modules(PC_PLPLOT QUIET IMPORTED_TARGET plplot-c++)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(PLplot REQUIRED_VARS PC_PLPLOT_FOUND PC_PLPLOT_LIBRARIES VERSION_VAR PC_PLPLOT_VERSION)
if(PLplot_FOUND AND NOT TARGET PLplot::plplotcxx)
  add_library(PLplot::plplotcxx INTERFACE IMPORTED)
  target_link_libraries(PLplot::plplotcxx INTERFACE PkgConfig::PC_PLPLOT)
endif()
