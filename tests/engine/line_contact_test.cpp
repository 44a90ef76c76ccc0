#include "engine/line_contact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/support/paper_scene.h"

namespace ringtol::engine {
namespace {

// A few products and powers, each within an ulp or two of its value: far below this.
constexpr double kRoundingRelative = 1e-13;
// Palmgren's power law against Hertz's logarithmic approach of two cylinders: within 10 %
// at peak pressures from 0.1 to 6 GPa (the rolling-bearing range; computed for the cases
// below: 3 % for the article's rollers, 1 % for the 800 mm table's). Beyond, the
// logarithm bends away from any power law.
constexpr double kPowerLawAgainstHertz = 0.10;

constexpr Material kSteel207{207e9, 0.3};  // the steel of Palmgren's fit
constexpr Material kAluminium{70e9, 0.33};

// Penetration [m] under Q = k delta^(10/9).
double Penetration(double force, double stiffness) { return std::pow(force / stiffness, 1.0 / kLineContactExponent); }

TEST(LineContact, ContactModulusOfLikeBodiesIsHalfTheirPlaneStrainModulus) {
  const double plane_strain = kSteel207.youngs_modulus / (1.0 - 0.3 * 0.3);
  EXPECT_NEAR(ContactModulus(kSteel207, kSteel207), plane_strain / 2.0, kRoundingRelative * plane_strain);
  const double mixed = 1.0 / ((1.0 - 0.33 * 0.33) / 70e9 + (1.0 - 0.3 * 0.3) / 207e9);
  EXPECT_NEAR(ContactModulus(kAluminium, kSteel207), mixed, kRoundingRelative * mixed);
  EXPECT_EQ(ContactModulus(kAluminium, kSteel207), ContactModulus(kSteel207, kAluminium));
}

TEST(LineContact, ReproducesPalmgrensFormulaForSteelOnSteel) {
  const double modulus = ContactModulus(kSteel207, kSteel207);
  for (const double force : {1.0, 19.3, 200.0, 5000.0}) {           // [N]
    for (const double length_mm : {2.0, 4.0, 20.0, 60.0}) {
      const double palmgren_mm = 3.84e-5 * std::pow(force, 0.9) / std::pow(length_mm, 0.8);
      const double penetration = Penetration(force, LineContactStiffness(modulus, length_mm * 1e-3));
      EXPECT_NEAR(penetration, palmgren_mm * 1e-3, kRoundingRelative * palmgren_mm * 1e-3)
          << force << " N over " << length_mm << " mm";
    }
  }
}

TEST(LineContact, StiffnessScalesWithTheContactModulusAndLengthToTheEightNinths) {
  const double k = LineContactStiffness(100e9, 0.004);
  EXPECT_NEAR(LineContactStiffness(50e9, 0.004), k / 2.0, kRoundingRelative * k);
  const double longer = k * std::pow(3.0, 8.0 / 9.0);
  EXPECT_NEAR(LineContactStiffness(100e9, 0.012), longer, kRoundingRelative * longer);
}

// Johnson, Contact Mechanics (1985), ch. 5: two cylinders of radius r and length l pressed
// together by Q approach, measured between their centres, by
//   2 (Q / l) (1 - nu^2) / (pi E) (2 ln(4 r / b) - 1),   b = sqrt(4 (Q / l) (r / 2) / (pi E*)).
double HertzApproachOfTwoCylinders(const Material& m, double radius, double length, double force) {
  const double per_length = force / length;
  const double modulus = ContactModulus(m, m);
  const double half_width = std::sqrt(4.0 * per_length * (radius / 2.0) / (std::numbers::pi * modulus));
  return 2.0 * per_length * (1.0 - m.poisson_ratio * m.poisson_ratio) / (std::numbers::pi * m.youngs_modulus) *
         (2.0 * std::log(4.0 * radius / half_width) - 1.0);
}

TEST(LineContact, AgreesWithHertzsApproachOfTwoCylindersAtBearingPressures) {
  struct Case {
    double radius, length, force;  // [m], [m], [N]
  };
  // The article's rollers at its preload; the 800 mm table's at its preload; a loaded bearing.
  for (const Case c : {Case{0.005, 0.004, 19.3}, Case{0.020, 0.020, 200.0}, Case{0.005, 0.004, 1000.0}}) {
    const double hertz = HertzApproachOfTwoCylinders(kSteel207, c.radius, c.length, c.force);
    const double fit = Penetration(c.force, LineContactStiffness(ContactModulus(kSteel207, kSteel207), c.length));
    EXPECT_NEAR(fit, hertz, kPowerLawAgainstHertz * hertz) << c.force << " N";
  }
}

TEST(LineContact, ContactLengthIsTheNarrowerOfRollerAndRing) {
  Scene scene = testing::PaperScene();  // ring 6 mm thick
  scene.rollers[0].width = 0.004;
  scene.rollers[1].width = 0.010;
  EXPECT_EQ(ContactLength(scene, 0), 0.004);
  EXPECT_EQ(ContactLength(scene, 1), 0.006);
  EXPECT_EQ(ContactLength(scene, 2), 0.006);  // no width: a scene built in code
}

TEST(LineContact, TheSoftestContactSetsTheScenesLawAndTheDampingStays) {
  Scene scene = testing::PaperScene();
  for (Roller& roller : scene.rollers) roller.width = 0.004;
  scene.ring.material = kAluminium;
  scene.rollers[2].width = 0.002;
  ContactLaw damping;
  damping.max_damping = 123.0;
  damping.full_damping_penetration = 4e-6;
  const ContactLaw law = MaterialContactLaw(scene, damping);
  const double softest = LineContactStiffness(ContactModulus(kAluminium, Material{}), 0.002);
  EXPECT_NEAR(law.stiffness, softest, kRoundingRelative * softest);
  EXPECT_EQ(law.exponent, kLineContactExponent);
  EXPECT_EQ(law.model, damping.model);
  EXPECT_EQ(law.max_damping, 123.0);
  EXPECT_EQ(law.full_damping_penetration, 4e-6);
  EXPECT_LT(RollerContactStiffness(scene, 2), RollerContactStiffness(scene, 0));
}

}  // namespace
}  // namespace ringtol::engine
