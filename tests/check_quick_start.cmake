# Fails when the README's quick start stops being the main job alone:
#   - its first command must install .ci/packages, configure without the tests, as a unity
#     build (the faster cold build, docs/performance.md), and build only the ringtol target;
#   - .ci/packages must hold nothing that only the tests need (.ci/test-packages), and no
#     package may be in both lists;
#   - docs/dependencies.md's install lines must list the same packages in the same order.
# Run as: cmake -DROOT=<source dir> -P check_quick_start.cmake
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/report_failures.cmake)

set(failures "")
file(STRINGS "${ROOT}/.ci/packages" main)
file(STRINGS "${ROOT}/.ci/test-packages" tests_only)
foreach(package ${main})
  if(package IN_LIST tests_only)
    list(APPEND failures ".ci/packages: ${package} is also in .ci/test-packages")
  endif()
  if(package MATCHES "gtest|gmock|benchmark|chromium|openturns|^python3-|hdf5-tools")
    list(APPEND failures ".ci/packages: ${package} serves only the tests; it belongs in .ci/test-packages")
  endif()
endforeach()

file(READ "${ROOT}/README.md" readme)
string(REGEX MATCH "```sh\n([^\n]*)\n```" first_block "${readme}")
set(first "${CMAKE_MATCH_1}")
foreach(part "xargs -a .ci/packages" "-DRINGTOL_TESTS=OFF" "-DCMAKE_UNITY_BUILD=ON" "cmake --build build --target ringtol " "build/ringtol campaign")
  string(FIND "${first}" "${part}" at)
  if(at EQUAL -1)
    list(APPEND failures "README.md: the quick start's first command lacks '${part}'")
  endif()
endforeach()
string(FIND "${first}" "test-packages" at)
if(NOT at EQUAL -1)
  list(APPEND failures "README.md: the quick start's first command installs the tests' packages")
endif()

file(READ "${ROOT}/docs/dependencies.md" dependencies)
string(REPLACE ";" " " main_line "${main}")
string(REPLACE ";" " " tests_line "${tests_only}")
foreach(line "--no-install-recommends ${main_line}\n" "--no-install-recommends ${tests_line}\n")
  string(FIND "${dependencies}" "${line}" at)
  if(at EQUAL -1)
    list(APPEND failures "docs/dependencies.md: §1 has no install line ending in '${line}'")
  endif()
endforeach()

report_failures("the quick start is not the main job alone" "quick start checked" ${failures})
