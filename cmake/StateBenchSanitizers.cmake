# Sanitizer builds (a second build folder, e.g. build-asan, in .ci/run):
#   cmake -S . -B build-asan -DSTATEBENCH_SANITIZE=address,undefined
# With -DSTATEBENCH_FUZZ=ON (clang) the same build also has the fuzz targets of tests/fuzz.
# statebench_set_sanitizers(<target>) adds the flags per target (no global CMAKE_CXX_FLAGS).
# UndefinedBehaviorSanitizer aborts on its first report (-fno-sanitize-recover) so a report
# fails the test that triggered it instead of scrolling past.
set(STATEBENCH_SANITIZE "" CACHE STRING
    "Comma-separated sanitizers for every StateBench target (e.g. address,undefined); empty: none")
set(STATEBENCH_SANITIZE_EXCLUDE "" CACHE STRING
    "Comma-separated checks left out (-fno-sanitize=), e.g. the costly alignment,null of UBSan")

option(STATEBENCH_FUZZ "Build the libFuzzer targets of tests/fuzz (clang only)" OFF)
if(STATEBENCH_FUZZ AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "STATEBENCH_FUZZ needs clang: configure with -DCMAKE_CXX_COMPILER=clang++")
endif()

function(statebench_set_sanitizers target)
  # Coverage for libFuzzer in the libraries the fuzz targets exercise (not in the test programs:
  # it costs a third more compile time and slows the tests).
  get_target_property(type ${target} TYPE)
  if(STATEBENCH_FUZZ AND type MATCHES "LIBRARY")
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
  if(NOT STATEBENCH_SANITIZE)
    return()
  endif()
  set(flags -fsanitize=${STATEBENCH_SANITIZE} -fno-omit-frame-pointer)
  if(STATEBENCH_SANITIZE MATCHES "undefined")
    list(APPEND flags -fno-sanitize-recover=undefined)
  endif()
  if(STATEBENCH_SANITIZE_EXCLUDE)
    list(APPEND flags -fno-sanitize=${STATEBENCH_SANITIZE_EXCLUDE})
  endif()
  target_compile_options(${target} PRIVATE ${flags})
  target_link_options(${target} PRIVATE ${flags})
endfunction()
