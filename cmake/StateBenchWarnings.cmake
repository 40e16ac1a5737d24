include(StateBenchSanitizers)

# statebench_set_warnings(<target>): warnings per target, never through global flags; also the
# sanitizers of a sanitizer build (StateBenchSanitizers.cmake), since every target calls it.
function(statebench_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-unused-parameter)
  statebench_set_sanitizers(${target})
endfunction()
