# polarcam_pkg_config_target(PACKAGE MODULE TARGET): a Debian library that ships a pkg-config file but no usable
# CMake configuration, found through pkg-config module MODULE and defined as the imported target TARGET
# (PACKAGE_FOUND and PACKAGE_VERSION as find_package sets them). A macro: the find module's caller sees the results.
macro(polarcam_pkg_config_target package module target)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(PC_${package} QUIET IMPORTED_TARGET ${module})
  include(FindPackageHandleStandardArgs)
  find_package_handle_standard_args(${package} REQUIRED_VARS PC_${package}_FOUND PC_${package}_LIBRARIES
                                    VERSION_VAR PC_${package}_VERSION)
  if(${package}_FOUND AND NOT TARGET ${target})
    add_library(${target} INTERFACE IMPORTED)
    target_link_libraries(${target} INTERFACE PkgConfig::PC_${package})
  endif()
endmacro()
