# statebench_set_warnings(<target>): warnings per target, never through global flags.
function(statebench_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-unused-parameter)
endfunction()
