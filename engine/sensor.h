// The runout sensor of docs/model.md §5: a laser triangulator fixed in the frame looks along
// a ray from the nominal centre at a fixed angle and reads how far out the ring's bore is.
// Its signal contains the centre's motion and the bore's own form passing by.
#pragma once

#include <span>

#include "engine/contact.h"
#include "engine/profile.h"

namespace ringtol::engine {

struct SensorReading {
  double distance = 0.0;    // [m] from the origin along the sensor ray to the bore
  double ring_theta = 0.0;  // [rad] ring body angle seen (warm start for the next reading)
};

// Cosines and sines of the angles a reading needs, which move in small steps from one
// reading to the next along a trajectory: pass the same object to every reading of a
// trajectory and most sincos calls, the bulk of a reading's cost, are saved.
struct SensorTrack {
  NearbyAngle sensor;
  NearbyAngle aim;   // the sensor's direction in the ring's body frame
  NearbyAngle bore;  // the bore angle being iterated on
};

// Exact ray/bore intersection by bracketed Newton iteration in the ring body angle.
// Requires the origin to lie inside the bore (always true for a supported ring). The
// answer does not depend on theta_guess or track (to round-off).
SensorReading ReadSensor(const PolarProfile& ring, const BodyPose& ring_pose, double sensor_angle,
                         double theta_guess, SensorTrack* track = nullptr);

struct Runout {
  // [m] largest rise or fall between neighbouring extremes of the signal over one
  // revolution, treating it as periodic: "peak to nearest valley" (docs/model.md §5).
  double peak_to_nearest_valley = 0.0;
  double total = 0.0;  // [m] max - min over the revolution
};

// Runout of a signal sampled uniformly over one revolution, treated as periodic (a
// closing sample equal to the first is harmless). Plateaus count as one extreme. Empty
// input gives zeros.
Runout MeasureRunout(std::span<const double> signal);

}  // namespace ringtol::engine
