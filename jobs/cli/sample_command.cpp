#include "jobs/cli/sample_command.h"

#include <fstream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "engine/units.h"
#include "jobs/campaign/campaign_file.h"
#include "jobs/cli/results_output.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/sampling_file.h"
#include "jobs/inputs/scene_writer.h"
#include "sampling/spectrum.h"

namespace ringtol::jobs {
int RunSample(const SampleCommand& command, std::ostream& out) {
  const std::string source = command.file.string();
  // A campaign file is a sampling file too: its solver and spec are not needed here.
  SamplingPlan plan = ReadSamplingFile(command.file, kCampaignTables);
  OverridePlan(plan, command.samples, command.seed);
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
  std::ofstream csv = OpenOptionalOutput(command.csv, "--csv");

  fmt::print(out, "sampling file     {}\n", source);
  fmt::print(out, "base scene        {}\n", plan.scene_file.string());
  fmt::print(out, "design            {}, {} samples, seed {}, {} coordinates\n",
             sampling::DesignName(plan.design.kind), plan.samples, plan.seed, sampling.sampler.dimension());
  fmt::print(out, "catalogue         {}\n", plan.catalogue.version);
  for (const sampling::ComponentScale& s : sampling.sampler.scales()) {
    fmt::print(out, "calibrated        {}: {} <= {:.4g} um for {:.4g} % of parts: scale {:.4g} um ({} draws)\n",
               s.component, sampling::FormMeasureName(s.measure), s.tolerance * units::kMicrometresPerMetre,
               100 * s.coverage, s.calibration.scale * units::kMicrometresPerMetre, s.calibration.draws);
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

}  // namespace ringtol::jobs
