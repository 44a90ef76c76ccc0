#include "engine/units.h"

#include <cstdio>

namespace ringtol::units {

std::string ShowMillimetres(double metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", InMillimetres(metres));
  return text;
}

}  // namespace ringtol::units
