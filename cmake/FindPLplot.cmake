# PLplot (Debian: libplplot-dev, plplot-driver-cairo). Debian's plplotConfig.cmake refers to the bindings of
# every language (Tcl, Qt, wxWidgets...) and fails without them, so this module asks pkg-config for the C++
# library only. Defines the imported target PLplot::plplotcxx.
include(PolarcamPkgConfig)
polarcam_pkg_config_target(PLplot plplot-c++ PLplot::plplotcxx)
