// How far a scene's penalty contact law shapes its answer (docs/model.md §4, "When the
// law matters"). Every error moves the ring's centre through changes of the contacts'
// gaps (solvers/linear.h); a compliant contact shares each such change with the spring,
// and so shrinks or redirects the centre's response. That share does not depend on how
// large the errors are (the response is linear in them), so it is measured once, on the
// error-free assembly: the static response of the centre to a small outward offset of
// each roller in turn (a change of that contact's gap: every error is a combination of
// such changes), under the scene's law and under the same law made so stiff that every
// contact sinks a thousandth as far.
#pragma once

#include "engine/scene.h"

namespace ringtol::solvers {

struct ContactCompliance {
  // False for rigid contact, and where the error-free assembly has no usable static
  // equilibrium (its own solve reports why); nothing below is set then.
  bool assessed = false;
  // The error-free assembly's deepest contact at its static equilibrium: its roller, its
  // penetration (F / k)^(1/e) [m] and its force F [N].
  int roller = -1;
  double penetration = 0.0;
  double force = 0.0;
  // [-] >= 0: ||R - S|| / ||S|| (spectral norms), where the 2 x Z matrices R and S map the
  // contacts' gap changes to the centre's static displacement under the scene's law and
  // under the stiff one. So for every pattern of errors, the law moves the centre by at
  // most this share of the largest displacement errors of the same size can cause.
  double response_change = 0.0;
};

// Solves the error-free assembly's statics 2 (Z + 1) times for Z rollers, with the
// quasistatic rung's default options: milliseconds. Never throws for a numerical outcome.
ContactCompliance AssessContactCompliance(const engine::Scene& scene);

}  // namespace ringtol::solvers
