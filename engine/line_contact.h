// The contact law of a roller in a bore from what the two are made of and how wide they
// touch: Hertzian line contact in the power-law form bearing engineers use, Palmgren's
// (docs/model.md §4, "The law of the materials").
//
// Palmgren's fit of a roller's contact with a raceway, steel on steel (Harris and
// Kotzalas, Rolling Bearing Analysis; Palmgren, Ball and Roller Bearing Engineering), is
//   delta = 3.84e-5 Q^0.9 / l^0.8         (delta in mm, Q in N, l in mm).
// Dimensionally it is delta = C (Q / (E* l))^0.9 l^0.1, with E* the contact modulus,
//   1 / E* = (1 - nu_1^2) / E_1 + (1 - nu_2^2) / E_2,
// and C = 3.84e-5 [E*_steel in N/mm^2]^0.9 = 1.3635 (steel: E = 207 GPa, nu = 0.3): a
// number without unit, so the same form carries the fit to other materials. Solved for Q,
//   Q = k delta^(10/9),   k = E* l^(8/9) / C^(10/9) = 0.7086 E* l^(8/9)   (SI).
// A power law is used because the approach of a two-dimensional contact has no value of
// its own: Hertz's line contact fixes the pressure, not how far bodies of finite size
// approach, which depends on where it is measured (Johnson, Contact Mechanics, §5.6).
#pragma once

#include "engine/scene.h"

namespace ringtol::engine {

// e of the law of the materials: Palmgren's delta ~ Q^0.9, solved for Q.
inline constexpr double kLineContactExponent = 10.0 / 9.0;

// E* [Pa] of two bodies in contact: 1 / E* = (1 - nu_a^2) / E_a + (1 - nu_b^2) / E_b.
double ContactModulus(const Material& a, const Material& b);

// k [N/m^(10/9)] of Q = k delta^(10/9) for a line contact `length` [m] > 0 long between
// bodies of contact modulus E* [Pa] > 0.
double LineContactStiffness(double contact_modulus, double length);

// [m] how long roller i touches the bore: its width, or the ring's thickness where that is
// narrower or the roller has no width (a scene built in code).
double ContactLength(const Scene& scene, int i);

// k [N/m^(10/9)] of roller i's contact with the bore, from the two materials and
// ContactLength.
double RollerContactStiffness(const Scene& scene, int i);

// `law` with the exponent 10/9 and the stiffness of the scene's softest contact (the
// smallest RollerContactStiffness): the engine has one law for every contact, and the
// softest sinks furthest, so it is the one whose compliance could matter. The damping and
// the model are left as `law` has them. Precondition: at least one roller, a ring of
// positive thickness.
ContactLaw MaterialContactLaw(const Scene& scene, ContactLaw law);

}  // namespace ringtol::engine
