# Host build conventions shared by hal_sim/, host_tools/ and tests/.
#
# ggins_host_warnings: the one warning set of every host target (C and C++),
# linked PRIVATE: target_link_libraries(<target> PRIVATE ggins_host_warnings).
# C++ is ISO C++17 (-Wpedantic); host C (hal_sim, the firmware's unit tests) may
# use the GNU quad-precision type __float128 and its Q constants for independent
# truth, so it is not pedantic. (The firmware has its own, stricter set:
# GGINS_FW_WARNINGS in firmware/CMakeLists.txt.)
add_library(ggins_host_warnings INTERFACE)
target_compile_options(ggins_host_warnings INTERFACE -Wall -Wextra -Werror $<$<COMPILE_LANGUAGE:CXX>:-Wpedantic>)

# ggins_command(<name> <what>): registers the subcommand `ggins <name>` (the
# program ggins-<name> beside the dispatcher) with its one-line description;
# host_tools/CMakeLists.txt writes the dispatcher's table from these calls.
function(ggins_command name what)
  set_property(GLOBAL APPEND PROPERTY GGINS_COMMANDS "${name}")
  set_property(GLOBAL PROPERTY "GGINS_COMMAND_WHAT_${name}" "${what}")
endfunction()
