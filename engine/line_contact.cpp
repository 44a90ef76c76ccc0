#include "engine/line_contact.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "engine/units.h"

namespace ringtol::engine {
namespace {

// Palmgren's steel-on-steel fit, delta [mm] = kPalmgren Q^0.9 [N] / l^0.8 [mm], and the
// steel it was made for.
constexpr double kPalmgren = 3.84e-5;
constexpr Material kPalmgrenSteel{207e9, 0.3};

// C of delta = C (Q / (E* l))^0.9 l^0.1, without unit: 1.3635.
double PalmgrenConstant() {
  const double steel = ContactModulus(kPalmgrenSteel, kPalmgrenSteel) / units::kPascalsPerMegapascal;  // [N/mm^2]
  return kPalmgren * std::pow(steel, 0.9);
}

}  // namespace

double ContactModulus(const Material& a, const Material& b) {
  const auto compliance = [](const Material& m) { return (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus; };
  return 1.0 / (compliance(a) + compliance(b));
}

double LineContactStiffness(double contact_modulus, double length) {
  static const double scale = std::pow(PalmgrenConstant(), -kLineContactExponent);
  return scale * contact_modulus * std::pow(length, 2.0 - kLineContactExponent);
}

double ContactLength(const Scene& scene, int i) {
  const double width = scene.rollers[static_cast<std::size_t>(i)].width;
  return width > 0.0 ? std::min(width, scene.ring.thickness) : scene.ring.thickness;
}

double RollerContactStiffness(const Scene& scene, int i) {
  const Material& roller = scene.rollers[static_cast<std::size_t>(i)].material;
  return LineContactStiffness(ContactModulus(scene.ring.material, roller), ContactLength(scene, i));
}

ContactLaw MaterialContactLaw(const Scene& scene, ContactLaw law) {
  double softest = RollerContactStiffness(scene, 0);
  for (int i = 1; i < static_cast<int>(scene.rollers.size()); ++i) {
    softest = std::min(softest, RollerContactStiffness(scene, i));
  }
  law.stiffness = softest;
  law.exponent = kLineContactExponent;
  return law;
}

}  // namespace ringtol::engine
