# Fails when a library's files include, directly or through the project's own headers,
# a header of a library it must not depend on (docs/architecture.md):
#   - engine, sampling, solvers and analysis are pure computation: no TOML, HDF5, MPI,
#     command line, JSON or formatting library, and nothing of a layer above them;
#   - in jobs/, each library sees only the libraries below it (the store sees of the
#     allocation only its plain-data outcome, allocation_outcome.h), the report, the input
#     files and the allocation never see mpi.h, and no command but `ringtol campaign` and
#     `ringtol allocate` (and main, which starts MPI for them) compiles against mpi.h.
# Run as: cmake -DROOT=<source dir> -P check_layering.cmake
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/report_failures.cmake)

# Every project header a file reaches, and every system header it reaches, through the
# project's quoted includes (system headers are not followed).
function(reach file out_project out_system)
  set(seen "")
  set(system "")
  set(queue "${file}")
  while(queue)
    list(POP_FRONT queue current)
    if(current IN_LIST seen OR NOT EXISTS "${ROOT}/${current}")
      continue()
    endif()
    list(APPEND seen "${current}")
    file(STRINGS "${ROOT}/${current}" lines REGEX "^#include ")
    foreach(line ${lines})
      if(line MATCHES "^#include \"([^\"]+)\"")
        list(APPEND queue "${CMAKE_MATCH_1}")
      elseif(line MATCHES "^#include <([^>]+)>")
        list(APPEND system "${CMAKE_MATCH_1}")
      endif()
    endforeach()
  endwhile()
  list(REMOVE_DUPLICATES system)
  set(${out_project} "${seen}" PARENT_SCOPE)
  set(${out_system} "${system}" PARENT_SCOPE)
endfunction()

# "a b/c.h" as the regex of what may be reached: folders a/ and the single header b/c.h.
function(allowed_pattern list out)
  string(REPLACE " " "/|" pattern "${list}/")
  string(REPLACE ".h/" ".h$" pattern "${pattern}")  # a single header, not a folder
  set(${out} "${pattern}" PARENT_SCOPE)
endfunction()
set(application_headers "^(mpi\\.h|hdf5\\.h|H5Cpp\\.h|toml\\+\\+/|CLI/|fmt/|nlohmann/)")
# folder = the project folders it may reach = system headers it must not reach (regex)
set(rules
  "engine=engine=${application_headers}"
  "sampling=engine sampling=${application_headers}"
  "solvers=engine solvers=${application_headers}"
  "analysis=engine sampling solvers analysis=${application_headers}"
  "jobs/inputs=engine sampling solvers jobs/inputs=^(mpi\\.h|hdf5\\.h|CLI/)"
  "jobs/campaign=engine sampling solvers jobs/inputs jobs/campaign=^(mpi\\.h|hdf5\\.h|CLI/)"
  "jobs/allocation=engine sampling solvers analysis jobs/inputs jobs/campaign jobs/allocation=^(mpi\\.h|hdf5\\.h|CLI/)"
  "jobs/store=engine sampling solvers analysis jobs/inputs jobs/campaign jobs/allocation/allocation_outcome.h jobs/store=^(mpi\\.h|CLI/)"
  "jobs/pool=engine sampling solvers analysis jobs/inputs jobs/campaign jobs/allocation jobs/store jobs/pool=^(hdf5\\.h|CLI/)"
  "jobs/report=engine sampling solvers analysis jobs/inputs jobs/campaign jobs/allocation jobs/store jobs/report=^(mpi\\.h|hdf5\\.h|CLI/)"
  "jobs/studies=engine sampling solvers analysis jobs/inputs jobs/campaign jobs/report jobs/studies=^(mpi\\.h|hdf5\\.h|CLI/)"
  # Inside the store: the shared result types and shard naming sit below everything, the
  # sample table and HDF5 machinery below the two stores, and neither store sees the other.
  "jobs/store/results_check.h=jobs/store/results_check.h=^(mpi\\.h|CLI/)"
  "jobs/store/shards.h=jobs/store/shards.h=^(mpi\\.h|CLI/)"
  "jobs/store/hdf5_file.h=engine sampling jobs/store/hdf5_file.h=^(mpi\\.h|CLI/)"
  "jobs/store/identity_attributes.h=engine sampling jobs/store/hdf5_file.h jobs/store/identity_attributes.h=^(mpi\\.h|CLI/)"
  "jobs/store/sample_table.h=jobs/campaign engine sampling solvers analysis jobs/inputs jobs/store/results_check.h jobs/store/hdf5_file.h jobs/store/sample_table.h=^(mpi\\.h|CLI/)"
  "jobs/store/allocation_store.h=jobs/allocation/allocation_outcome.h jobs/campaign engine sampling solvers analysis jobs/inputs jobs/store/results_check.h jobs/store/shards.h jobs/store/allocation_store.h=^(mpi\\.h|CLI/)"
  "jobs/store/campaign_store.h=jobs/campaign engine sampling solvers analysis jobs/inputs jobs/store/results_check.h jobs/store/shards.h jobs/store/campaign_store.h=^(mpi\\.h|CLI/)")

set(failures "")
foreach(rule ${rules})
  string(REPLACE "=" ";" parts "${rule}")
  list(GET parts 0 folder)
  list(GET parts 1 allowed)
  list(GET parts 2 forbidden_system)
  allowed_pattern("${allowed}" allowed)
  if(folder MATCHES "\\.h$")  # a single header's own rule
    set(files "${folder}")
  else()
    file(GLOB_RECURSE files RELATIVE ${ROOT} ${ROOT}/${folder}/*.h ${ROOT}/${folder}/*.cpp)
  endif()
  foreach(f ${files})
    reach("${f}" project system)
    foreach(header ${project})
      if(NOT header MATCHES "^(${allowed})")
        list(APPEND failures "${f} reaches ${header} (${folder} may use only ${allowed})")
      endif()
    endforeach()
    foreach(header ${system})
      if(header MATCHES "${forbidden_system}")
        list(APPEND failures "${f} reaches <${header}> (forbidden in ${folder})")
      endif()
    endforeach()
  endforeach()
endforeach()

# The command line: only the commands that run the pool (campaign, allocate), what they
# share (pool_run) and main (which starts MPI for them) see MPI.
file(GLOB files RELATIVE ${ROOT} ${ROOT}/jobs/cli/*.h ${ROOT}/jobs/cli/*.cpp)
foreach(f ${files})
  if(f MATCHES "^jobs/cli/((campaign|allocate)_command\\.(h|cpp)|pool_run\\.(h|cpp)|main\\.cpp)$")
    continue()
  endif()
  reach("${f}" project system)
  if("mpi.h" IN_LIST system)
    list(APPEND failures "${f} reaches <mpi.h>: only `ringtol campaign` and `ringtol allocate` run the MPI pool")
  endif()
endforeach()

report_failures("layering violations" "layering ok" ${failures})
