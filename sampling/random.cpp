#include "sampling/random.h"

#include <Random123/philox.h>

namespace ringtol::sampling {

std::uint64_t RandomBits(std::uint64_t seed, RandomStream stream, std::uint64_t a, std::uint64_t b,
                         std::uint64_t c) {
  using Philox = r123::Philox4x64;
  const Philox::ctr_type counter = {{a, b, c, 0}};
  const Philox::key_type key = {{seed, static_cast<std::uint64_t>(stream)}};
  return Philox{}(counter, key)[0];
}

}  // namespace ringtol::sampling
