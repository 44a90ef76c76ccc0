// A tolerance allocation ready to run: its file read and checked, every candidate's
// campaign built on first use, and the driver that turns the search
// (analysis/allocation.h) into rounds of simulation.
//
// Common random numbers: a candidate's campaign is the current design's campaign file
// with the candidate's classes, so every candidate has the same design, seed and sample
// count, and sample i gets the same design point u in every candidate
// (SampleEvaluator: u = design.Point(i)); inspection redraws are keyed by (seed, sample,
// input, attempt). Candidates differ only in the scales the classes give the same draws.
//
// Stages and roles (docs/allocation.md): a candidate's samples are simulated in stages
// [0, n_1), [n_1, n_2), ..., n_1 = first_samples, n_{k+1} = min(2 n_k, N). The screening
// rung (EvaluationRole::kScreen) simulates the first stage; where its error bound settles
// the candidate (infeasible on a bounded constraint, or feasible on every constraint) it
// is settled by the screen. Otherwise the confirming rung (the file's [solver]) simulates
// stage after stage until every constraint is decided, or N samples leave it undecided.
//
// Determinism: the driver is a pure function of the samples on disk. Each round simulates
// the next stage of every unsettled candidate of the search's current batch; the batch
// size is the file's, not the rank count; so a resumed run, or one on any number of ranks,
// simulates the same candidates at the same samples and comes to the same outcome.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "analysis/allocation.h"
#include "jobs/allocation/allocation_file.h"
#include "jobs/allocation/allocation_outcome.h"
#include "jobs/campaign/campaign.h"
#include "jobs/campaign/sample_record.h"

namespace ringtol::jobs {

class Allocation {
 public:
  // Reads the allocation file. Throws InputError for everything ReadAllocationFile refuses.
  explicit Allocation(const std::filesystem::path& file);
  ~Allocation();

  const AllocationPlan& plan() const { return plan_; }
  const AllocationIdentity& identity() const { return identity_; }
  const analysis::AllocationSpace& space() const { return space_; }
  std::int64_t samples() const { return plan_.campaign.sampling.samples; }  // N
  // The outputs the constraints name, each once, in the order of kOutputNames.
  const std::vector<std::string>& stored_outputs() const { return stored_outputs_; }

  // The campaign of a candidate in a role, built on first use (its sampler calibrated
  // through a shared sampling::CalibrationCache, so each class is calibrated once) and
  // kept. Thread-safe. Throws InputError where the candidate's classes cannot make a
  // sampler (a class without a row at a part's diameter is refused when the file is read).
  const Campaign& CandidateCampaign(std::int64_t candidate, EvaluationRole role) const;
  // Design points of samples [0, N), row-major [N, d]: the same for every candidate.
  std::vector<double> DesignPoints() const;

 private:
  AllocationPlan plan_;
  analysis::AllocationSpace space_;
  AllocationIdentity identity_;
  std::vector<std::string> stored_outputs_;
  std::shared_ptr<sampling::CalibrationCache> calibrations_;
  mutable std::mutex mutex_;
  mutable std::map<std::pair<std::int64_t, EvaluationRole>, std::unique_ptr<Campaign>> campaigns_;
};

// Samples of one candidate in one role: what a round simulates.
struct RoundSegment {
  EvaluationRole role = EvaluationRole::kConfirm;
  std::int64_t candidate = 0;
  std::int64_t begin = 0;  // samples [begin, end)
  std::int64_t end = 0;
  friend bool operator==(const RoundSegment&, const RoundSegment&) = default;
};

// Simulates candidate samples, one thread at a time (one per computing thread): keeps a
// SampleEvaluator per candidate and role it has seen.
class AllocationEvaluator {
 public:
  explicit AllocationEvaluator(const Allocation& allocation);
  ~AllocationEvaluator();
  // The record of sample `sample` of `candidate` in `role` (record.index = sample), with
  // its design point and drawn values dropped: the results file keeps u once for all
  // candidates. Never throws for the sample's own failure (SampleEvaluator::Evaluate).
  SampleRecord Evaluate(EvaluationRole role, std::int64_t candidate, std::int64_t sample);

 private:
  const Allocation* allocation_;
  std::map<std::pair<std::int64_t, EvaluationRole>, std::unique_ptr<SampleEvaluator>> evaluators_;
};

// What the driver reads of the samples simulated so far (a results file, through an
// adapter in the layer that owns it).
class StoredSamples {
 public:
  virtual ~StoredSamples() = default;
  // Whether every sample of [begin, end) is on record.
  virtual bool AllDone(EvaluationRole role, std::int64_t candidate, std::int64_t begin, std::int64_t end) const = 0;
  virtual std::vector<SampleStatus> Status(EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                                           std::int64_t end) const = 0;
  // One of Allocation::stored_outputs().
  virtual std::vector<double> Output(EvaluationRole role, const std::string& output, std::int64_t candidate,
                                     std::int64_t begin, std::int64_t end) const = 0;
  // The screening rung's error bound in d_trajectory_mm [mm].
  virtual std::vector<double> ErrorBound(std::int64_t candidate, std::int64_t begin, std::int64_t end) const = 0;
};

class AllocationDriver {
 public:
  explicit AllocationDriver(const Allocation& allocation);
  ~AllocationDriver();

  // Plays the search forward over the stored samples, as far as they reach, and returns
  // what the next round must simulate: one segment per unsettled candidate of the batch,
  // its current stage whole (after an interruption some of its samples may be on record
  // already: the pool skips those). Empty when the search is over. Call it again once
  // those samples are stored.
  std::vector<RoundSegment> Advance(const StoredSamples& samples);

  bool done() const;
  std::int64_t simulated() const;  // candidates settled by simulation so far
  // What is known so far (complete once done()).
  AllocationOutcome Outcome(const StoredSamples& samples) const;
  std::int64_t rounds() const;  // rounds played so far

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace ringtol::jobs
