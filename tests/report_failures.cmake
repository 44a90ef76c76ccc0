# The one way a repository check ends: every failure on its own line under `heading`, and
# a failed run; or `passed` as a status line.
function(report_failures heading passed)
  if(ARGN)
    string(REPLACE ";" "\n" report "${ARGN}")
    message(FATAL_ERROR "${heading}:\n${report}")
  endif()
  message(STATUS "${passed}")
endfunction()
