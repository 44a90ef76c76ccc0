#include "jobs/campaign.h"

#include <chrono>
#include <cmath>
#include <exception>
#include <limits>

#include "jobs/input_error.h"
#include "jobs/scene_writer.h"
#include "solvers/dynamic.h"

namespace ringtol::jobs {
namespace {

constexpr double kMillimetresPerMetre = 1e3;

CampaignPlan ReadWithOverrides(const std::filesystem::path& file, std::optional<std::int64_t> samples,
                               std::optional<std::uint64_t> seed) {
  CampaignPlan plan = ReadCampaignFile(file);
  OverridePlan(plan.sampling, samples, seed);
  return plan;
}

}  // namespace

Campaign::Campaign(const std::filesystem::path& file, std::optional<std::int64_t> samples,
                   std::optional<std::uint64_t> seed)
    : plan_(ReadWithOverrides(file, samples, seed)), sampling_(MakeSampling(plan_.sampling, file.string())) {
  simulation_.steps = plan_.solver.steps;
  simulation_.path_tolerance = plan_.solver.path_tolerance;

  identity_.ringtol_version = RINGTOL_VERSION;
  identity_.catalogue_version = plan_.sampling.catalogue.version;
  identity_.campaign_path = file.string();
  identity_.campaign_file = plan_.sampling.text;
  identity_.base_scene = WriteScene(plan_.sampling.scene);
  identity_.design = sampling::DesignName(plan_.sampling.design.kind);
  identity_.solver = plan_.solver.name;
  identity_.seed = plan_.sampling.seed;
  identity_.inputs = sampling_.sampler.inputs();
  identity_.spec = plan_.spec;
}

std::unique_ptr<solvers::Solver> Campaign::MakeSolver() const {
  solvers::DynamicOptions dynamic;
  dynamic.relative_tolerance = plan_.solver.relative_tolerance;
  return solvers::MakeSolver(plan_.solver.name, dynamic);
}

SampleEvaluator::SampleEvaluator(const Campaign& campaign, EvaluatorFaults faults)
    : campaign_(&campaign),
      design_(campaign.sampling().design.dimension(), campaign.sampling().design.options()),
      solver_(campaign.MakeSolver()),
      faults_(std::move(faults)),
      u_(static_cast<std::size_t>(campaign.sampling().design.dimension())) {}

SampleRecord SampleEvaluator::Evaluate(std::int64_t index) {
  const auto start = std::chrono::steady_clock::now();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  SampleRecord record;
  record.index = index;
  record.outputs.fill(kNaN);
  design_.Point(index, u_);
  record.u = u_;
  record.values.assign(campaign_->sampling().sampler.inputs().size(), kNaN);

  std::optional<sampling::SampledAssembly> assembly;
  try {
    assembly = campaign_->sampling().sampler.Realise(index, u_);
    record.values = assembly->values;
    record.redraws = assembly->redraws;
  } catch (const std::exception& e) {
    record.status = SampleStatus::kSamplingFailed;
    record.message = e.what();
  }
  if (assembly) {
    try {
      if (faults_.before_simulate) faults_.before_simulate(index);
      solvers::SimulationResult result = solvers::Simulate(assembly->scene, *solver_, campaign_->simulation());
      if (faults_.after_simulate) faults_.after_simulate(index, result);
      record.steps = result.steps;
      record.status = FromSolverStatus(result.status);
      record.message = result.message;
      if (result.status == solvers::Status::kOk) {
        double max_force = -std::numeric_limits<double>::infinity();
        for (const solvers::RollerForceRange& range : result.contact_force) max_force = std::max(max_force, range.max);
        const std::array<double, kOutputCount> outputs = {
            result.d_trajectory * kMillimetresPerMetre, result.dist_init * kMillimetresPerMetre,
            result.static_offset * kMillimetresPerMetre, result.runout * kMillimetresPerMetre,
            result.runout_total * kMillimetresPerMetre, result.min_contact_force, max_force};
        bool finite = true;
        for (std::size_t k = 0; k < kOutputCount; ++k) finite = finite && std::isfinite(outputs[k]);
        if (finite) {
          record.outputs = outputs;
        } else {
          record.status = SampleStatus::kNonFiniteOutput;
          record.message = "the solver reported ok but an output is not finite";
        }
      }
    } catch (const std::exception& e) {
      record.status = SampleStatus::kException;
      record.message = e.what();
    }
  }
  record.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return record;
}

}  // namespace ringtol::jobs
