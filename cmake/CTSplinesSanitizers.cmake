# SPDX-License-Identifier: GPL-3.0-or-later
# Sanitizer and fuzzing builds (docs/fuzzing.md).
#   CTSPLINES_SANITIZE        sanitizers for every target of the project, e.g. "address,undefined"
#                             (clang or gcc); any report aborts (-fno-sanitize-recover=all).
#   CTSPLINES_BUILD_FUZZERS   the libFuzzer targets of Testing/Fuzz (clang only); the project's
#                             code then also gets coverage instrumentation (fuzzer-no-link).
# Third-party libraries (VTK, OpenCASCADE, CGAL's compiled parts) stay uninstrumented.
set(CTSPLINES_SANITIZE "" CACHE STRING
  "Sanitizers for the whole project (-fsanitize=<value>), e.g. address,undefined; empty: none")
option(CTSPLINES_BUILD_FUZZERS "Build the libFuzzer targets of Testing/Fuzz (clang)" OFF)

if(CTSPLINES_BUILD_FUZZERS AND NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "CTSPLINES_BUILD_FUZZERS needs clang (libFuzzer), not ${CMAKE_CXX_COMPILER_ID}: "
    "configure with -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14")
endif()

set(_ctsplines_sanitize "${CTSPLINES_SANITIZE}")
if(CTSPLINES_BUILD_FUZZERS)
  # Coverage for libFuzzer in every library the targets link; the runtime comes with the
  # targets' own -fsanitize=fuzzer.
  if(_ctsplines_sanitize)
    string(APPEND _ctsplines_sanitize ",fuzzer-no-link")
  else()
    set(_ctsplines_sanitize "fuzzer-no-link")
  endif()
endif()
if(_ctsplines_sanitize)
  message(STATUS "CTSplines: -fsanitize=${_ctsplines_sanitize}")
  add_compile_options("-fsanitize=${_ctsplines_sanitize}" -fno-sanitize-recover=all
    -fno-omit-frame-pointer)
  add_link_options("-fsanitize=${_ctsplines_sanitize}")
endif()
