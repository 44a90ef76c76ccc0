// The scene file's vocabulary, listed once: the key names and the names of the values
// that ReadScene (scene_file.h) accepts and WriteScene (scene_writer.h) writes, so that a
// written scene always reads back. Units are in the key names (docs/architecture.md).
#pragma once

#include <string_view>

#include "engine/conventions.h"
#include "engine/enum_names.h"
#include "engine/scene.h"

namespace ringtol::jobs {

// How the [motion] table states a motion law.
enum class MotionKind { kArticle, kTestBench, kPiecewise };

inline constexpr NameTable<engine::RollerMount, 2> kRollerMountNames = {
    {{engine::RollerMount::kFixed, "fixed"}, {engine::RollerMount::kSpring, "spring"}}};
inline constexpr NameTable<engine::ShapePhaseReference, 2> kShapePhaseReferenceNames = {
    {{engine::ShapePhaseReference::kRadial, "radial"}, {engine::ShapePhaseReference::kGlobal, "global"}}};
inline constexpr NameTable<engine::ContactLaw::Model, 2> kContactModelNames = {
    {{engine::ContactLaw::Model::kRigid, "rigid"}, {engine::ContactLaw::Model::kPenalty, "penalty"}}};
inline constexpr NameTable<MotionKind, 3> kMotionKindNames = {
    {{MotionKind::kArticle, "article"}, {MotionKind::kTestBench, "test_bench"}, {MotionKind::kPiecewise, "piecewise"}}};

// Keys, in whichever tables they appear.
namespace scene_key {
inline constexpr std::string_view kAngleDeg = "angle_deg";
inline constexpr std::string_view kCentreRadiusMm = "centre_radius_mm";
inline constexpr std::string_view kCutoffUpr = "cutoff_upr";
inline constexpr std::string_view kDynamicCoefficient = "dynamic_coefficient";
inline constexpr std::string_view kErrorMotionCutoffUpr = "error_motion_cutoff_upr";
inline constexpr std::string_view kExponent = "exponent";
inline constexpr std::string_view kFriction = "friction";
inline constexpr std::string_view kFullDampingPenetrationMm = "full_damping_penetration_mm";
inline constexpr std::string_view kHarmonics = "harmonics";
inline constexpr std::string_view kInnerRadiusMm = "inner_radius_mm";
inline constexpr std::string_view kLaw = "law";
inline constexpr std::string_view kMassKg = "mass_kg";
inline constexpr std::string_view kMasslessSpringRollers = "massless_spring_rollers";
inline constexpr std::string_view kMaxDampingNSPerM = "max_damping_N_s_per_m";
inline constexpr std::string_view kMeanDeviationMm = "mean_deviation_mm";
inline constexpr std::string_view kMount = "mount";
inline constexpr std::string_view kName = "name";
inline constexpr std::string_view kOuterRadiusMm = "outer_radius_mm";
inline constexpr std::string_view kPhaseLockedRollers = "phase_locked_rollers";
inline constexpr std::string_view kPoissonRatio = "poisson_ratio";
inline constexpr std::string_view kRadialOffsetMm = "radial_offset_mm";
inline constexpr std::string_view kRadiusMm = "radius_mm";
inline constexpr std::string_view kRateDegPerS = "rate_deg_per_s";
inline constexpr std::string_view kRevolutions = "revolutions";
inline constexpr std::string_view kResolutionUm = "resolution_um";
inline constexpr std::string_view kRollingWithoutSlip = "rolling_without_slip";
inline constexpr std::string_view kSegments = "segments";
inline constexpr std::string_view kSettleS = "settle_s";
inline constexpr std::string_view kShapePhaseReference = "shape_phase_reference";
inline constexpr std::string_view kSpinInertiaKgM2 = "spin_inertia_kg_m2";
inline constexpr std::string_view kSpinPhaseDeg = "spin_phase_deg";
inline constexpr std::string_view kSpringAxisDeg = "spring_axis_deg";
inline constexpr std::string_view kSpringPreloadN = "spring_preload_N";
inline constexpr std::string_view kSpringStiffnessNPerM = "spring_stiffness_N_per_m";
inline constexpr std::string_view kSpringTravelLimitMm = "spring_travel_limit_mm";
inline constexpr std::string_view kStaticCoefficient = "static_coefficient";
inline constexpr std::string_view kStictionVelocityMmPerS = "stiction_velocity_mm_per_s";
inline constexpr std::string_view kStiffnessNPerME = "stiffness_N_per_m_e";
inline constexpr std::string_view kTangentialOffsetMm = "tangential_offset_mm";
inline constexpr std::string_view kThicknessMm = "thickness_mm";
inline constexpr std::string_view kTransitionVelocityMmPerS = "transition_velocity_mm_per_s";
inline constexpr std::string_view kWidthMm = "width_mm";
inline constexpr std::string_view kYoungsModulusGPa = "youngs_modulus_GPa";
}  // namespace scene_key

}  // namespace ringtol::jobs
