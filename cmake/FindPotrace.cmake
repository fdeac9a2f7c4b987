# potrace's library (Debian: libpotrace-dev), which ships neither a pkg-config file nor a CMake configuration:
# its header and library found by name. Defines the imported target Potrace::potrace.
find_path(Potrace_INCLUDE_DIR potracelib.h)
find_library(Potrace_LIBRARY potrace)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Potrace REQUIRED_VARS Potrace_LIBRARY Potrace_INCLUDE_DIR)
if(Potrace_FOUND AND NOT TARGET Potrace::potrace)
  add_library(Potrace::potrace UNKNOWN IMPORTED)
  set_target_properties(Potrace::potrace PROPERTIES IMPORTED_LOCATION "${Potrace_LIBRARY}"
                                                    INTERFACE_INCLUDE_DIRECTORIES "${Potrace_INCLUDE_DIR}")
endif()
mark_as_advanced(Potrace_INCLUDE_DIR Potrace_LIBRARY)
