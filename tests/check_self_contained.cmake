# Fails when the repository leans on something a clone does not have:
#   - a file that points outside the repository (the team's reference shelf beside it),
#   - a file that speaks of the team's issue numbers, which a user cannot look up,
#   - a relative link in README.md or docs/*.md whose target is not in the repository.
# Run as: cmake -DROOT=<source dir> -P check_self_contained.cmake
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/report_failures.cmake)

file(GLOB_RECURSE files RELATIVE ${ROOT} ${ROOT}/*)
list(FILTER files EXCLUDE REGEX "^(\\.git/|build[^/]*/)")

set(outside "\\.\\./shared|shared/doc[s]")
set(issue_number "[Ii][Ss][Ss][Uu][Ee] #?[0-9]")
set(failures "")
foreach(f ${files})
  file(STRINGS "${ROOT}/${f}" lines REGEX "${outside}|${issue_number}")
  foreach(line ${lines})
    list(APPEND failures "${f}: ${line}")
  endforeach()
endforeach()

file(GLOB documents RELATIVE ${ROOT} ${ROOT}/README.md ${ROOT}/CHANGELOG.md ${ROOT}/docs/*.md)
foreach(document ${documents})
  get_filename_component(folder "${ROOT}/${document}" DIRECTORY)
  file(READ "${ROOT}/${document}" text)
  # Square brackets and semicolons would bend CMake's lists: take them out first.
  string(REPLACE ";" "," text "${text}")
  string(REPLACE "](" "@link@" text "${text}")
  string(REGEX REPLACE "[][]" "" text "${text}")
  string(REGEX MATCHALL "@link@[^)#: ]+[)#]" links "${text}")
  foreach(link ${links})
    string(REGEX REPLACE "^@link@([^)#]+)[)#]$" "\\1" target "${link}")
    if(NOT EXISTS "${folder}/${target}")
      list(APPEND failures "${document}: link to ${target}, which is not in the repository")
    endif()
  endforeach()
endforeach()

report_failures("the repository does not stand alone" "self-contained" ${failures})
