// A pure layer that reads TOML: check_layering.cmake must refuse it.
#pragma once

#include <toml++/toml.h>
