// Scene files: the TOML description of one assembly (docs/model.md §1–§4), read into an
// engine::Scene in SI units. examples/paper/scene.toml is the reference example; its
// comments and this header together define the format.
//
// Units are in the key names and converted on reading: *_mm -> m, *_deg -> rad,
// *_mm_per_s -> m/s; other keys are SI already (N, N/m, N/m^e, N s/m, kg, kg/m^3, kg m^2).
// Integers are accepted where numbers are expected; nan and inf are rejected.
//
//   [ring]                       required
//     inner_radius_mm            required, > 0: nominal bore radius R
//     outer_radius_mm            required, > inner_radius_mm
//     thickness_mm               required, > 0 (axial)
//     density_kg_per_m3 | mass_kg   exactly one, > 0; density gives the annulus mass
//                                rho pi (Ro^2 - Ri^2) t
//     spin_inertia_kg_m2         > 0, default the annulus m (Ro^2 + Ri^2) / 2
//     mean_deviation_mm          default 0
//     harmonics                  default []; [{ order = integer 1..1000, amplitude_mm >= 0,
//                                phase_deg = 0 }, ...] in the ring frame
//     measured_profile           optional: a roundness tester's export fitted on reading,
//                                { file = "ring.csv", orders = 20, keep_eccentricity = false }
//       file                     required: a CSV file (jobs/inputs/profile_csv.h), relative to the
//                                scene file's folder (ParseScene, which has text but no file:
//                                relative to the current directory); an absolute path as is
//       orders                   required, integer 1..1000: orders 0..orders are fitted
//                                (sampling/profile_fit.h, jobs/inputs/profile_csv.h)
//       keep_eccentricity        default false: order 1 is the tester's set-up eccentricity
//                                and is dropped; true keeps it
//       reference                default "nominal": the export's size counts; "own_mean": its
//                                form alone, about its own mean, on a ring of any size
//                                The fit a_0 + sum_n C_n cos(n theta + phi_n) joins the ring's
//                                own keys: orders 2..orders (1..orders when kept) are appended
//                                to harmonics (equal orders add up), and with reference
//                                "nominal" mean_deviation_mm gains a_0 - inner_radius_mm when
//                                the file holds radii (radius_mm), a_0 when it holds deviations
//                                (deviation_mm, deviation_um); that offset beyond 1 % of
//                                inner_radius_mm is refused as another ring's profile, and a
//                                form (sum of C_n) beyond 1 % as deviations in another unit.
//                                With radii and no other ring errors, r(theta) is the fitted
//                                outline. CSV and fit errors are InputErrors
//                                with this key's position and path in front, e.g.
//                                "scene.toml:9:20: ring.measured_profile: ring.csv:7: ..."
//   [roller_positions]           optional: mean_deviation_mm, harmonics (as above), the
//                                radial position series evaluated at each roller's angle
//   [[rollers]]                  at least 3
//     name                       default "roller<i>", i = 1, 2, ... in file order; unique
//     angle_deg                  required
//     radius_mm                  required, > 0 and < ring.inner_radius_mm: r_b
//     centre_radius_mm           > 0, default inner_radius_mm - radius_mm
//     radial_offset_mm, tangential_offset_mm    default 0
//     mount                      required, "fixed" or "spring"
//     spring_stiffness_N_per_m   >= 0, required for springs   } all four only with
//     spring_preload_N           > 0, required for springs    } mount = "spring"
//     spring_axis_deg            default angle_deg            }
//     spring_travel_limit_mm     > 0, default radius_mm       }
//     width_mm                   required, > 0
//     density_kg_per_m3 | mass_kg   exactly one, > 0; density gives the solid cylinder
//                                rho pi r_b^2 width
//     spin_inertia_kg_m2         > 0, default the solid cylinder m r_b^2 / 2
//     shape_phase_reference      "radial" (default) or "global" (engine/conventions.h)
//     spin_phase_deg             default 0
//     mean_deviation_mm, harmonics   as for the ring, in the roller frame
//   [contact]                    optional
//     law                        "rigid" or "penalty" (default)
//     stiffness_N_per_m_e        > 0, default 1e7
//     exponent                   >= 1 and <= 3, default 1.5
//     max_damping_N_s_per_m      >= 0, default 1e5
//     full_damping_penetration_mm   > 0, default 0.001
//   [friction]                   optional
//     static_coefficient         >= 0, default 0.61
//     dynamic_coefficient        >= 0, default 0.47
//     stiction_velocity_mm_per_s    > 0, default 10
//     transition_velocity_mm_per_s  > stiction_velocity_mm_per_s, default 50
//   [sensor]                     optional
//     angle_deg                  default 0
//     resolution_um              >= 0 and <= 1000, default 0.1: counter-moves the swing ignores
//     cutoff_upr                 >= 0 and <= 100000, default 0 (unfiltered): the swing's
//                                Gaussian filter cutoff [undulations per revolution]
//   [motion]                     optional; the imposed rotation (engine/motion_law.h), read
//                                by the dynamic solver only
//     law                        "article" (default), "test_bench" or "piecewise"
//     settle_s                   >= 0, default 0.5; article and test_bench: at rest first
//     rate_deg_per_s             non-zero, default 270; article only (negative: clockwise)
//     revolutions                > 0, default 3; article only: the law's listed span (the
//                                ring keeps turning after it)
//     segments                   piecewise only, required: [{ duration_s > 0,
//                                acceleration_deg_per_s2 = 0, start_rate_deg_per_s (absent:
//                                continue the previous segment's end rate) }, ...]
//   [dynamics]                   optional; what the dynamic solver models (engine::DynamicModel)
//     friction                   true (default) or false
//     rolling_without_slip       false (default) or true
//     massless_spring_rollers    false (default) or true
//
// Failure: InputError (jobs/inputs/input_error.h) for a missing, unreadable or malformed file,
// an unknown or missing key (anywhere, including inside harmonic tables), a wrong type,
// a value out of range, a measured profile that is missing, unreadable or cannot support
// the orders asked for, a profile whose |mean_deviation| + sum of amplitudes reaches its
// radius (the polar form breaks down there), and a roller that does not fit in the ring
// (engine::CheckGeometry). A ring or roller that is not convex is NOT an input error: the
// solvers report it as a status, so a sweep can include such cases.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "engine/scene.h"

namespace ringtol::jobs {

// Reads and validates a scene file. Messages name the file as given; files it names
// (ring.measured_profile.file) are resolved against its folder.
engine::Scene ReadScene(const std::filesystem::path& file);

// The same for TOML text already in memory; source_name stands for the file in messages.
// Files the text names are resolved against the current directory.
engine::Scene ParseScene(std::string_view toml_text, const std::string& source_name);

}  // namespace ringtol::jobs
