# Sanitizer builds (a second build folder, e.g. build-asan, in .ci/run):
#   cmake -S . -B build-asan -DSTATEBENCH_SANITIZE=address,undefined
# statebench_set_sanitizers(<target>) adds the flags per target (no global CMAKE_CXX_FLAGS).
# UndefinedBehaviorSanitizer aborts on its first report (-fno-sanitize-recover) so a report
# fails the test that triggered it instead of scrolling past.
set(STATEBENCH_SANITIZE "" CACHE STRING
    "Comma-separated sanitizers for every StateBench target (e.g. address,undefined); empty: none")

function(statebench_set_sanitizers target)
  if(NOT STATEBENCH_SANITIZE)
    return()
  endif()
  set(flags -fsanitize=${STATEBENCH_SANITIZE} -fno-omit-frame-pointer)
  if(STATEBENCH_SANITIZE MATCHES "undefined")
    list(APPEND flags -fno-sanitize-recover=undefined)
  endif()
  target_compile_options(${target} PRIVATE ${flags})
  target_link_options(${target} PRIVATE ${flags})
endfunction()
