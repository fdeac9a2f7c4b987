# dxflib (Debian: libdxflib-dev), which ships a pkg-config file but no CMake configuration.
# Defines the imported target Dxflib::dxflib.
include(PolarcamPkgConfig)
polarcam_pkg_config_target(Dxflib dxflib Dxflib::dxflib)
