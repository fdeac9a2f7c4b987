# libserial (Debian: libserial-dev) ships a pkg-config file but no CMake config. Defines LibSerial::LibSerial.
include(PolarcamPkgConfig)
polarcam_pkg_config_target(LibSerial libserial LibSerial::LibSerial)
