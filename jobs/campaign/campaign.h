// A campaign ready to run: its plan read and checked, the sampler calibrated, the design
// made, the solver chosen. Every rank builds its own from the same file, so a sample is a
// pure function of (campaign, index) wherever it is computed.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "jobs/campaign/campaign_file.h"
#include "jobs/campaign/campaign_identity.h"
#include "jobs/campaign/sample_record.h"
#include "solvers/simulation.h"
#include "solvers/solver.h"

namespace ringtol::jobs {

class Campaign {
 public:
  // Reads the campaign file, applies the overrides and calibrates. Throws InputError for
  // everything ReadCampaignFile and MakeSampling refuse.
  Campaign(const std::filesystem::path& file, std::optional<std::int64_t> samples, std::optional<std::uint64_t> seed);
  // The campaign a results file holds, rebuilt from the campaign file's text and base scene
  // stored in it (the files on disk may have moved or changed), at its sample count and
  // seed: replays its samples. Draws with the stored calibrations where the file has them
  // (CampaignIdentity::calibrations), so only files written before they were stored
  // calibrate. Throws InputError when the stored text no longer reads (another ringtol
  // version) or makes other inputs than the file lists.
  Campaign(const CampaignIdentity& stored, std::int64_t samples);
  // A campaign of a plan built in memory (a tolerance allocation's candidate: the current
  // design with other classes); `source_name` names it in messages, `calibrations` (may be
  // null) shares spectrum calibrations with other campaigns, `known_scales` are
  // calibrations made before (MakeSampling). Throws InputError as MakeSampling does.
  Campaign(CampaignPlan plan, const std::string& source_name,
           std::shared_ptr<sampling::CalibrationCache> calibrations,
           std::vector<sampling::ComponentScale> known_scales = {});

  const CampaignPlan& plan() const { return plan_; }
  const Sampling& sampling() const { return sampling_; }
  const CampaignIdentity& identity() const { return identity_; }
  std::int64_t samples() const { return plan_.sampling.samples; }
  const solvers::SimulationOptions& simulation() const { return plan_.solver.simulation; }
  // Whether sample `index` is an independent draw, usable for distributions: every sample,
  // except the AB matrices of a Saltelli design, which re-use the A and B coordinates.
  bool IndependentDraw(std::int64_t index) const;
  // How many of samples [0, end) are independent draws, in constant time.
  std::int64_t IndependentDraws(std::int64_t end) const;
  // A solver of the campaign's settings (each thread makes its own): solvers::MakeSolver.
  std::unique_ptr<solvers::Solver> MakeSolver() const;

 private:
  CampaignPlan plan_;
  Sampling sampling_;
  CampaignIdentity identity_;
};

// Seams for tests: faults injected into one sample, to show they stay in that sample.
struct EvaluatorFaults {
  std::function<void(std::int64_t index)> before_simulate;                             // may throw
  std::function<void(std::int64_t index, solvers::SimulationResult&)> after_simulate;  // may spoil outputs
};

// Draws samples of one campaign without simulating them: each sample's design point, drawn
// values and redraws, exactly as SampleEvaluator draws them, for replays of samples whose
// inputs a results file does not keep. Not thread-safe (it owns a Design, whose Sobol'
// engine is stateful): one per thread.
class SampleDrawer {
 public:
  explicit SampleDrawer(const Campaign& campaign);

  // A record of the sample's index, u, values and redraws. Its status is kSamplingFailed,
  // with the sampler's message and NaN values, when the assembly cannot be realised, and
  // kPending (drawn, not simulated) otherwise; `assembly`, when given, receives the
  // realised assembly. Never throws for the sample's own failure.
  SampleRecord Draw(std::int64_t index, std::optional<sampling::SampledAssembly>* assembly = nullptr);

 private:
  const Campaign* campaign_;
  sampling::Design design_;
  std::vector<double> u_;
};

// Fills `record`'s status, message, steps, rung and, when the simulation is ok, its outputs
// (kOutputs' order and units), error bound and off-bore shares from one simulation;
// `life_asked`: whether its options read the life (SimulationOptions::life). A non-finite
// output the life's absence does not explain makes the record kNonFiniteOutput.
void RecordSimulation(const solvers::SimulationResult& result, bool life_asked, SampleRecord& record);

// Computes samples of one campaign. Not thread-safe (it owns a Design, whose Sobol'
// engine is stateful): one per thread.
class SampleEvaluator {
 public:
  explicit SampleEvaluator(const Campaign& campaign, EvaluatorFaults faults = {});

  // Never throws for the sample's own failure: an exception inside sampling or the solver,
  // or a non-finite output, becomes the record's status and message. Outputs are NaN
  // unless status is kOk.
  SampleRecord Evaluate(std::int64_t index);

 private:
  const Campaign* campaign_;
  SampleDrawer drawer_;
  std::unique_ptr<solvers::Solver> solver_;
  // The campaign's settings without the path's points: a record holds only metrics.
  solvers::SimulationOptions simulation_;
  EvaluatorFaults faults_;
};

}  // namespace ringtol::jobs
