// A command other than `ringtol campaign` that reaches MPI: check_layering.cmake must refuse it.
#include "jobs/pool/pool.h"
