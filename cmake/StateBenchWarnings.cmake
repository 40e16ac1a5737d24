include(StateBenchSanitizers)

# statebench_set_warnings(<target>): warnings per target, never through global flags; also the
# sanitizers of a sanitizer build (StateBenchSanitizers.cmake), since every target calls it.
function(statebench_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-unused-parameter)
  statebench_set_sanitizers(${target})
endfunction()

# statebench_unity_library(<target>): a library compiled as batches of 8 of its sources (CI time:
# each batch parses the shared headers, Eigen and Ceres above all, once). Helpers in anonymous
# namespaces must therefore have names of their own across the library's files.
function(statebench_unity_library target)
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
endfunction()
