#include "jobs/sample_command.h"

#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "jobs/catalogue_file.h"
#include "jobs/input_error.h"
#include "jobs/sampling_file.h"
#include "jobs/scene_writer.h"
#include "sampling/spectrum.h"

namespace ringtol::jobs {
namespace {

constexpr double kMicrometresPerMetre = 1e6;

std::ofstream OpenOutput(const std::filesystem::path& file) {
  std::ofstream stream(file);
  if (!stream) throw InputError(file.string() + ": cannot open for writing");
  return stream;
}

}  // namespace

int RunSample(const SampleCommand& command, std::ostream& out) {
  const std::string source = command.file.string();
  SamplingPlan plan = ReadSamplingFile(command.file);
  if (command.samples) plan.samples = *command.samples;
  if (plan.design.kind == sampling::DesignKind::kLatinHypercube) plan.design.latin_samples = plan.samples;
  if (command.seed) plan.seed = plan.design.seed = *command.seed;
  if (command.index.has_value() != !command.scene.empty())
    throw InputError("--index and --scene go together: the sample to write and the file to write it to");
  if (command.index && (*command.index < 0 || *command.index >= plan.samples))
    throw InputError("--index " + std::to_string(*command.index) + ": allowed: 0.." + std::to_string(plan.samples - 1));
  if (!command.scene.empty()) {
    const std::filesystem::path folder = command.scene.parent_path().empty() ? "." : command.scene.parent_path();
    if (!std::filesystem::is_directory(folder))
      throw InputError(command.scene.string() + ": cannot be written: folder " + folder.string() + " does not exist");
  }
  Sampling sampling = MakeSampling(plan, source);
  std::ofstream csv, scene;
  if (!command.csv.empty()) csv = OpenOutput(command.csv);

  fmt::print(out, "sampling file     {}\n", source);
  fmt::print(out, "base scene        {}\n", plan.scene_file.string());
  fmt::print(out, "design            {}, {} samples, seed {}, {} coordinates\n",
             sampling::DesignName(plan.design.kind), plan.samples, plan.seed, sampling.sampler.dimension());
  fmt::print(out, "catalogue         {}\n", plan.catalogue.version);
  for (const sampling::ComponentScale& s : sampling.sampler.scales()) {
    fmt::print(out, "calibrated        {}: {} <= {:.4g} um for {:.4g} % of parts: scale {:.4g} um ({} draws)\n",
               s.component, sampling::FormMeasureName(s.measure), s.tolerance * kMicrometresPerMetre,
               100 * s.coverage, s.calibration.scale * kMicrometresPerMetre, s.calibration.draws);
  }

  const auto& inputs = sampling.sampler.inputs();
  if (csv.is_open()) {
    csv << "sample,redraws";
    for (const auto& input : inputs) csv << ',' << input.name;
    csv << '\n';
  }
  std::int64_t redraws = 0;
  for (std::int64_t i = 0; i < plan.samples; ++i) {
    const sampling::SampledAssembly a = sampling.sampler.Sample(sampling.design, i);
    redraws += a.redraws;
    if (csv.is_open()) {
      csv << i << ',' << a.redraws;
      for (const double v : a.values) csv << ',' << fmt::format("{}", v);
      csv << '\n';
    }
    if (command.index && *command.index == i) WriteSceneFile(a.scene, command.scene);
  }
  fmt::print(out, "drawn             {} assemblies, {} parts rejected by inspection and drawn again\n", plan.samples,
             redraws);
  if (csv.is_open()) fmt::print(out, "inputs            {} ({} columns)\n", command.csv.string(), inputs.size() + 2);
  if (command.index) fmt::print(out, "sample {}          {}\n", *command.index, command.scene.string());
  return 0;
}

int RunClasses(bool toml, std::ostream& out) {
  if (toml) {
    out << ShippedCatalogueText();
    return 0;
  }
  const sampling::ToleranceCatalogue c = ShippedCatalogue();
  auto names = [](const auto& k) {
    std::string text = k.name;
    for (const auto& a : k.aliases) text += ", " + a;
    return text;
  };
  fmt::print(out, "catalogue version {}\n", c.version);
  fmt::print(out, "\nrollers (ISO 492 outer ring), by outside diameter:\n");
  for (const auto& k : c.roller_classes) fmt::print(out, "  {:<20} {} ({} rows)\n", names(k), k.description, k.rows.size());
  fmt::print(out, "\nring bore circularity:\n");
  for (const auto& k : c.ring_classes) fmt::print(out, "  {:<20} {} ({} rows)\n", names(k), k.description, k.rows.size());
  fmt::print(out, "\nroller positions (zone diameter), by centre-circle diameter:\n");
  for (const auto& k : c.position_classes)
    fmt::print(out, "  {:<20} {} ({} rows)\n", names(k), k.description, k.rows.size());
  fmt::print(out, "\nsprings:\n");
  for (const auto& k : c.spring_classes) fmt::print(out, "  {:<20} {}\n", names(k), k.description);
  fmt::print(out, "\n`ringtol classes --toml` prints every row with its source.\n");
  return 0;
}

}  // namespace ringtol::jobs
