# polarcam_library(NAME [UNITY] [FUZZED] SOURCES a.cpp ... [FUZZED_SOURCES c.cpp ...] [PUBLIC deps ...]
#                  [PRIVATE deps ...])
# One library of the pipeline: its headers are included as "folder/file.hpp" from the source root, the project's
# warnings (and sanitizers) apply, and it links what it names. UNITY compiles its files in unity batches of eight
# when POLARCAM_UNITY_BUILD is on: the libraries whose files mostly parse, check and format (files, commands'
# studies, reports, machines' protocols) spend most of their compile time on the same library headers (the
# standard library, json, TOML, fmt, Eigen). The numerical libraries of the hot paths (digitizer, metrics,
# optimize, the Cartesian DDA) compile each file alone, so their code is optimised as it always was. A batched file's
# helpers in its unnamed namespace must not share a name with another file's of its library (they meet in one unit).
# FUZZED: the library holds parsers that the libFuzzer harnesses (fuzz/) feed, and gets the fuzzer's coverage
# instrumentation when POLARCAM_FUZZ is on; FUZZED_SOURCES: only these files of it do. The other libraries (the
# metrics, the searches, the pipeline, the reports, the dynamics) are not reached by any harness, and the coverage
# callbacks (every edge and every comparison) would only slow the sanitized test suite, which shares the build.
function(polarcam_library name)
  cmake_parse_arguments(L "UNITY;FUZZED" "" "SOURCES;FUZZED_SOURCES;PUBLIC;PRIVATE" ${ARGN})
  add_library(${name} ${L_SOURCES})
  if(L_UNITY)
    set_target_properties(${name} PROPERTIES UNITY_BUILD ${POLARCAM_UNITY_BUILD} UNITY_BUILD_BATCH_SIZE 8)
  endif()
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${L_PUBLIC} polarcam_options PRIVATE ${L_PRIVATE})
  if(POLARCAM_FUZZ AND L_FUZZED)  # libFuzzer's coverage in the parsers; the harnesses link the fuzzer (fuzz/)
    target_compile_options(${name} PRIVATE -fsanitize=fuzzer-no-link)
  elseif(POLARCAM_FUZZ AND L_FUZZED_SOURCES)
    set_property(SOURCE ${L_FUZZED_SOURCES} APPEND PROPERTY COMPILE_OPTIONS -fsanitize=fuzzer-no-link)
  endif()
endfunction()

# polarcam_cgal_unit(NAME SOURCE): CGAL confined to one translation unit, built as an object library that a
# polarcam library links privately. CGAL is slow to compile and compiles its users with -frounding-math, which
# the hot numerical code does not want.
function(polarcam_cgal_unit name source)
  add_library(${name} OBJECT ${source})
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(${name} PRIVATE CGAL::CGAL polarcam_digitizer polarcam_options)
  # GCC 12 reports -Wmaybe-uninitialized inside CGAL's kernel objects (Boost tuples) once sanitizers change
  # inlining; CGAL's arrangement handles are classes derived from its DCEL records without data of their own, and
  # its iterators downcast the records to them, which UBSan's vptr check reports.
  set(opts)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")  # clang has no such warning (the fuzz build, POLARCAM_FUZZ)
    set(opts -Wno-maybe-uninitialized)
  endif()
  if(POLARCAM_SANITIZE)
    list(APPEND opts -fno-sanitize=vptr)
  endif()
  set_source_files_properties(${source} PROPERTIES COMPILE_OPTIONS "${opts}")
endfunction()
