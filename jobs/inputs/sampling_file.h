// Sampling files: what to sample and how (scene, seed, [design], [tolerances.*],
// [catalogue]). They are the sampling half of a campaign file (jobs/campaign/campaign_file.h),
// which adds its solver and spec tables beside these; `ringtol sample` reads either. The
// format, key by key, is docs/inputs.md, "Campaign files".
//
// Classes are looked up at each roller's own diameter (2 r_b for shapes, twice its centre
// radius for positions) and the ring's bore diameter 2R. Failure: InputError naming the
// file, key, value and allowed range, for every key out of its range, an unknown class or
// a diameter its rows do not cover, a sample count the design cannot have, and what the
// sampler refuses (a capability too high to calibrate a form spectrum).
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/scene.h"
#include "sampling/assembly_sampler.h"
#include "sampling/catalogue.h"
#include "sampling/design.h"

namespace ringtol::jobs {

// What a [population.*] table says beyond its parts, for the report's view of the
// population (jobs/report/population_view.h); nothing here changes what is drawn.
struct PopulationSettings {
  int orders = 0;                  // each export fitted to orders 0..orders
  bool keep_eccentricity = false;  // its order 1 kept
  bool sized = true;               // reference = "nominal": each part's size about the nominal radius counts
  // `class`: the catalogue class the parts were made or bought to, checked to have a row at
  // the parts' diameter; none: the report picks the tightest every part meets.
  std::optional<std::string> class_name;
  sampling::ToleranceMode mode = sampling::ToleranceMode::kProcess;  // how that class is drawn
};

struct SamplingPlan {
  std::filesystem::path scene_file;  // as resolved
  engine::Scene scene;
  std::uint64_t seed = 1;
  sampling::DesignOptions design;  // groups filled by MakeSampling
  std::int64_t samples = 1000;
  sampling::InputGrouping grouping = sampling::InputGrouping::kSource;
  sampling::AssemblyTolerances tolerances;
  // [tolerances.rollers] diameter_series, which other roller classes are looked up with
  // (ToleranceOfClass).
  sampling::DiameterSeries roller_series = sampling::DiameterSeries::kSeries9;
  sampling::ToleranceCatalogue catalogue;  // shipped plus [catalogue]
  std::string text;                        // the file as read, for provenance
  // What identifies the measured parts of [population.*] beyond the file's text: a line of
  // settings and, per part, its export's name and the CRC-32 of its bytes; empty without
  // a population. A results file keeps it, and --resume refuses a population that changed.
  std::string population;
  // Set exactly where tolerances.ring_population / roller_population is.
  std::optional<PopulationSettings> ring_population, roller_population;
};

// `other_tables`: root tables of a larger file (a campaign file's [solver] and [spec]) that
// its own reader reads; accepted here as tables and otherwise left alone.
//
// `stored` (may be null): the file's text and its base scene as a results file keeps them
// (jobs/store/campaign_store.h); they stand in for the files on disk, which may have moved or
// changed since the campaign ran. `file` then only names the source in messages.
struct StoredSampling {
  std::string text;        // the sampling or campaign file as read
  std::string base_scene;  // the base scene as a scene file (jobs/inputs/scene_writer.h)
};
SamplingPlan ReadSamplingFile(const std::filesystem::path& file, std::span<const std::string_view> other_tables = {},
                              const StoredSampling* stored = nullptr);

// One component's tolerance as its [tolerances.*] table would give it with `class_name`
// (a name or alias of the catalogue) and `mode` in place of its class or numbers: the
// table's other keys (capability_cp, the spectrum, diameter_series) as `plan` read them,
// their defaults where the file has no such table; looked up at every part's diameter as
// ReadSamplingFile does. Only that component's entries of the result are set (the ring, or
// one per scene roller; springs: empty slots for fixed rollers). Throws the catalogue's
// std::invalid_argument for an unknown class or a diameter its rows do not cover.
sampling::AssemblyTolerances ToleranceOfClass(const SamplingPlan& plan, sampling::ErrorSource component,
                                              const std::string& class_name, sampling::ToleranceMode mode);

// A campaign's seed, as the file's `seed` and the commands' --seed take it: an integer from
// 0 to kMaxSeed. TOML's integers are signed 64-bit, which bounds the file's; --seed is held
// to the same range, so that every seed a command takes can be written in a file.
inline constexpr std::int64_t kMaxSeed = std::numeric_limits<std::int64_t>::max();
// "an integer >= 0 and <= 9223372036854775807", for messages.
std::string SeedAllowed();
// The seed written as `text` (decimal digits only: no sign, no hexadecimal, no spaces);
// empty when that is not a seed in range.
std::optional<std::uint64_t> SeedOfText(std::string_view text);

// Command-line overrides of the file's design.samples and seed (a Latin hypercube's size
// follows the sample count).
void OverridePlan(SamplingPlan& plan, std::optional<std::int64_t> samples, std::optional<std::uint64_t> seed);

// The sampler and the design of a plan, checked: the sample count fits the design.
struct Sampling {
  sampling::AssemblySampler sampler;
  sampling::Design design;
};
// `calibrations` (may be null) shares spectrum calibrations with other samplers
// (sampling::CalibrationCache); `known_scales` are calibrations made before
// (sampling::AssemblySamplerOptions::known_scales).
Sampling MakeSampling(const SamplingPlan& plan, const std::string& source_name,
                      std::shared_ptr<sampling::CalibrationCache> calibrations = nullptr,
                      std::vector<sampling::ComponentScale> known_scales = {});

}  // namespace ringtol::jobs
