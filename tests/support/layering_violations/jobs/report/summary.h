// A report header that reaches the MPI pool: check_layering.cmake must refuse it.
#pragma once

#include "jobs/pool/pool.h"
