// The environment every test that starts `ringtol campaign` (alone or under mpirun) puts
// before the command (docs/dependencies.md §4): root needs explicit permission; 3 ranks on 2
// cores need oversubscription; shared memory only (no network probing); no core binding,
// since ctest runs tests side by side. Open MPI's own start-up allocations are never freed,
// so leak checking is off for these runs (the library code is leak-checked by in-process
// tests).
#pragma once

#include <unistd.h>

#include <string>

namespace ringtol::testing {

inline const std::string kMpiEnvironment =
    "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
    "OMPI_MCA_pml=ob1 OMPI_MCA_btl=self,vader OMPI_MCA_btl_vader_single_copy_mechanism=none "
    "OMPI_MCA_hwloc_base_binding_policy=none ASAN_OPTIONS=detect_leaks=0 ";

// The launcher's prefix for `ranks` processes on this machine, root or not.
inline std::string Mpirun(int ranks) {
  return std::string(MPIEXEC_EXECUTABLE) + " -n " + std::to_string(ranks) +
         (geteuid() == 0 ? " --allow-run-as-root" : "") + " --oversubscribe ";
}

}  // namespace ringtol::testing
