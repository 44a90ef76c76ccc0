#include "jobs/campaign/campaign.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>

#include <fmt/format.h>

#include "jobs/inputs/input_error.h"
#include "jobs/inputs/scene_writer.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {


CampaignPlan ReadWithOverrides(const std::filesystem::path& file, std::optional<std::int64_t> samples,
                               std::optional<std::uint64_t> seed) {
  CampaignPlan plan = ReadCampaignFile(file);
  OverridePlan(plan.sampling, samples, seed);
  return plan;
}

CampaignPlan ReadStored(const CampaignIdentity& stored, std::int64_t samples) {
  const StoredSampling text{stored.campaign_file, stored.base_scene};
  CampaignPlan plan = ReadCampaignFile(stored.campaign_path, &text);
  OverridePlan(plan.sampling, samples, stored.seed);
  return plan;
}

}  // namespace

Campaign::Campaign(const std::filesystem::path& file, std::optional<std::int64_t> samples,
                   std::optional<std::uint64_t> seed)
    : Campaign(ReadWithOverrides(file, samples, seed), file.string(), nullptr) {}

Campaign::Campaign(const CampaignIdentity& stored, std::int64_t samples)
    : Campaign(ReadStored(stored, samples), stored.campaign_path + " (as stored)", nullptr, stored.calibrations) {
  const auto same = [](const sampling::SampledInput& a, const sampling::SampledInput& b) {
    return a.name == b.name && a.quantity == b.quantity && a.component == b.component && a.source == b.source &&
           a.roller == b.roller && a.order == b.order;
  };
  if (!std::equal(identity_.inputs.begin(), identity_.inputs.end(), stored.inputs.begin(), stored.inputs.end(), same)) {
    throw InputError(
        fmt::format("{}: the stored campaign makes other sampler inputs in this ringtol ({}) than in "
                    "the one that ran it ({}); its samples cannot be replayed",
                    stored.campaign_path, identity_.ringtol_version, stored.ringtol_version));
  }
  identity_.campaign_path = stored.campaign_path;
}

Campaign::Campaign(CampaignPlan plan, const std::string& source_name,
                   std::shared_ptr<sampling::CalibrationCache> calibrations,
                   std::vector<sampling::ComponentScale> known_scales)
    : plan_(std::move(plan)),
      sampling_(MakeSampling(plan_.sampling, source_name, std::move(calibrations), std::move(known_scales))) {
  const std::filesystem::path& file = plan_.file;

  identity_.ringtol_version = RINGTOL_VERSION;
  identity_.catalogue_version = plan_.sampling.catalogue.version;
  identity_.campaign_path = file.string();
  identity_.campaign_file = plan_.sampling.text;
  identity_.base_scene = WriteScene(plan_.sampling.scene);
  identity_.swing = plan_.sampling.scene.sensor_swing;
  identity_.error_motion_filter = plan_.sampling.scene.error_motion_filter;
  identity_.design = sampling::DesignName(plan_.sampling.design.kind);
  identity_.solver = solvers::SolverDescription(plan_.solver);
  identity_.seed = plan_.sampling.seed;
  identity_.inputs = sampling_.sampler.inputs();
  identity_.population = plan_.sampling.population;
  for (const engine::Roller& roller : plan_.sampling.scene.rollers) identity_.rollers.push_back(roller.name);
  identity_.spec = plan_.spec;
  identity_.life = plan_.solver.simulation.life;
  identity_.accuracy = plan_.solver.simulation.accuracy;
  identity_.calibrations = sampling_.sampler.scales();
}

bool Campaign::IndependentDraw(std::int64_t index) const {
  const sampling::Design& design = sampling_.design;
  return design.options().kind != sampling::DesignKind::kSaltelli || design.Locate(index).matrix < 2;
}

std::int64_t Campaign::IndependentDraws(std::int64_t end) const {
  const sampling::Design& design = sampling_.design;
  if (design.options().kind != sampling::DesignKind::kSaltelli) return end;
  // A and B lead each row: the first two of its samples_per_row.
  const std::int64_t per_row = design.samples_per_row();
  return 2 * (end / per_row) + std::min<std::int64_t>(end % per_row, 2);
}

std::unique_ptr<solvers::Solver> Campaign::MakeSolver() const { return solvers::MakeSolver(plan_.solver); }

SampleDrawer::SampleDrawer(const Campaign& campaign)
    : campaign_(&campaign),
      design_(campaign.sampling().design.dimension(), campaign.sampling().design.options()),
      u_(static_cast<std::size_t>(campaign.sampling().design.dimension())) {}

SampleRecord SampleDrawer::Draw(std::int64_t index, std::optional<sampling::SampledAssembly>* assembly) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  SampleRecord record;
  record.index = index;
  record.outputs.fill(kNaN);
  record.d_trajectory_error = kNaN;
  design_.Point(index, u_);
  record.u = u_;
  record.values.assign(campaign_->sampling().sampler.inputs().size(), kNaN);
  try {
    sampling::SampledAssembly drawn = campaign_->sampling().sampler.Realise(index, u_);
    record.values = drawn.values;
    record.redraws = drawn.redraws;
    if (assembly != nullptr) *assembly = std::move(drawn);
  } catch (const std::exception& e) {
    record.status = SampleStatus::kSamplingFailed;
    record.message = e.what();
  }
  record.draw_checksum = DrawChecksum(record);
  return record;
}

SampleEvaluator::SampleEvaluator(const Campaign& campaign, EvaluatorFaults faults)
    : campaign_(&campaign),
      drawer_(campaign),
      solver_(campaign.MakeSolver()),
      simulation_(campaign.simulation()),
      faults_(std::move(faults)) {
  simulation_.keep_trajectory = false;
}

void RecordSimulation(const solvers::SimulationResult& result, bool life_asked, SampleRecord& record) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  record.steps = result.steps;
  if (result.trajectory.rung && *result.trajectory.rung != solvers::Rung::kAuto) {
    record.rung = static_cast<std::int8_t>(*result.trajectory.rung);
  }
  record.status = FromSolverStatus(result.status);
  record.message = result.message;
  // A time-simulating rung's steady revolution is an output too: when it failed (a
  // contact opened, the law stopped before it) the sample did.
  const double steady_d_trajectory = result.steady ? result.steady->d_trajectory : result.d_trajectory;
  if (result.status == solvers::Status::kOk && result.steady && result.steady->status != solvers::Status::kOk) {
    record.status = FromSolverStatus(result.steady->status);
    record.message = "steady revolution: " + result.steady->message;
  }
  if (record.status == SampleStatus::kOk) {
    double max_force = -std::numeric_limits<double>::infinity();
    for (const solvers::RollerForceRange& range : result.contact_force) max_force = std::max(max_force, range.max);
    // A campaign reads the life unless told not to ([outputs] life = false, or an
    // allocation whose constraints name none of its outputs), or unless a roller left
    // the bore (SimulationResult::life_missing): its outputs are NaN then, and only then.
    const bool reads_life = life_asked && result.life_missing.empty();
    const solvers::LifeValues life = result.life.value_or(
        solvers::LifeValues{kNaN, kNaN, {kNaN, kNaN, kNaN, kNaN}});
    // One value for each row of kOutputs, in its order: a row left without one does not
    // compile, where a std::array's brace list would quietly give it 0.
    const auto outputs = std::to_array<double>({
        result.d_trajectory * units::kMillimetresPerMetre, result.dist_init * units::kMillimetresPerMetre,
        result.static_offset * units::kMillimetresPerMetre, result.runout * units::kMillimetresPerMetre,
        result.swing * units::kMillimetresPerMetre, result.min_contact_force, max_force,
        result.d_trajectory * units::kMillimetresPerMetre, steady_d_trajectory * units::kMillimetresPerMetre,
        life.d_trajectory * units::kMillimetresPerMetre, life.runout * units::kMillimetresPerMetre,
        life.error_motion.total * units::kMillimetresPerMetre,
        life.error_motion.synchronous * units::kMillimetresPerMetre,
        life.error_motion.asynchronous * units::kMillimetresPerMetre,
#ifdef RINGTOL_TEST_OUTPUT
        2.0 * result.d_trajectory * units::kMillimetresPerMetre,  // test_output_mm, tests/jobs/fake_output only
#endif
    });
    static_assert(outputs.size() == kOutputCount, "one value for each row of kOutputs");
    bool finite = true;
    for (std::size_t k = 0; k < kOutputCount; ++k) {
      finite = finite && (std::isfinite(outputs[k]) || (!reads_life && IsLifeOutput(k)));
    }
    if (finite) {
      record.outputs = outputs;
      for (const solvers::RollerForceRange& range : result.contact_force) {
        record.off_bore.push_back(units::kPercentPerFraction * range.off_bore);
      }
      record.d_trajectory_error = result.trajectory.error_estimate * units::kMillimetresPerMetre;
    } else {
      record.status = SampleStatus::kNonFiniteOutput;
      record.message = "the solver reported ok but an output is not finite";
    }
  }
}

SampleRecord SampleEvaluator::Evaluate(std::int64_t index) {
  const auto start = std::chrono::steady_clock::now();
  std::optional<sampling::SampledAssembly> assembly;
  SampleRecord record = drawer_.Draw(index, &assembly);
  if (assembly) {
    try {
      if (faults_.before_simulate) faults_.before_simulate(index);
      solvers::SimulationResult result = solvers::Simulate(assembly->scene, *solver_, simulation_);
      if (faults_.after_simulate) faults_.after_simulate(index, result);
      RecordSimulation(result, campaign_->simulation().life, record);
    } catch (const std::exception& e) {
      record.status = SampleStatus::kException;
      record.message = e.what();
    }
  }
  record.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return record;
}

}  // namespace ringtol::jobs
