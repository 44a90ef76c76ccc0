// The one place where file units meet SI. ringtol computes in metres, newtons, seconds and
// radians; input and output files speak millimetres, micrometres and degrees, with the
// unit in the key name (`amplitude_mm`, `phase_deg`). Every conversion multiplies or
// divides by one of these factors, so a value read and written back is the same double.
#pragma once

#include <numbers>
#include <string>

namespace ringtol::units {

inline constexpr double kMetresPerMillimetre = 1e-3;  // mm -> m (and mm/s -> m/s)
inline constexpr double kMetresPerMicrometre = 1e-6;  // um -> m
inline constexpr double kMillimetresPerMetre = 1e3;   // m -> mm
inline constexpr double kMicrometresPerMetre = 1e6;   // m -> um
inline constexpr double kMicrometresPerMillimetre = 1e3;  // mm -> um (output files in mm, errors in um)
inline constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;  // deg -> rad
inline constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;  // rad -> deg
inline constexpr double kPascalsPerGigapascal = 1e9;  // GPa -> Pa (Young's moduli)
inline constexpr double kPascalsPerMegapascal = 1e6;  // N/mm^2 -> Pa
inline constexpr double kSecondsPerMicrosecond = 1e-6;  // us -> s (the command line's --test-sample-us)
inline constexpr double kFractionPerPercent = 1e-2;   // % -> fraction (the *_percent keys)
inline constexpr double kPercentPerFraction = 1e2;    // fraction -> % (the *_percent outputs)
inline constexpr double kRadiansPerRevolution = 2.0 * std::numbers::pi;  // rev -> rad (a whole turn)

// SI values in the units files and messages state them. A length in millimetres divides by
// the factor its reader multiplied by, so a message shows what the file said.
constexpr double InMillimetres(double metres) { return metres / kMetresPerMillimetre; }
constexpr double InMicrometres(double metres) { return metres * kMicrometresPerMetre; }
constexpr double InDegrees(double radians) { return radians * kDegreesPerRadian; }

// A length as messages state it, in millimetres without the unit: six significant digits
// ("%g"), "inf" for an unbounded one: "302", "0.14", "1e-05".
std::string ShowMillimetres(double metres);

}  // namespace ringtol::units
