#include "jobs/cli/inputs_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <charconv>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "jobs/inputs/input_error.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {
namespace {

std::optional<std::int64_t> Index(std::string_view text) {
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < 0) return std::nullopt;
  return value;
}

}  // namespace

int RunInputs(const InputsCommand& command, std::ostream& out) {
  const CampaignReader reader(command.results);
  const std::int64_t samples = reader.samples();
  const std::size_t colon = command.samples.find(':');
  const std::optional<std::int64_t> first = Index(std::string_view(command.samples).substr(0, colon));
  const std::optional<std::int64_t> end =
      colon == std::string::npos ? (first ? std::optional<std::int64_t>(*first + 1) : std::nullopt)
                                 : Index(std::string_view(command.samples).substr(colon + 1));
  if (!first || !end || *first >= *end || *end > samples) {
    throw InputError(fmt::format("--samples {}: {} holds samples 0 to {}; allowed: FIRST or FIRST:END with 0 <= FIRST "
                                 "< END <= {}",
                                 command.samples, command.results.string(), samples - 1, samples));
  }
  const std::vector<sampling::SampledInput>& inputs = reader.identity().inputs;
  std::string header = "sample,status";
  for (std::size_t j = 0; j < inputs.size(); ++j) header += fmt::format(",u_{}", j);
  for (const sampling::SampledInput& input : inputs) header += "," + input.name;
  fmt::print(out, "{}\n", header);
  for (std::int64_t index = *first; index < *end; ++index) {
    const SampleRecord record = reader.ReadSample(index);
    std::string row = fmt::format("{},{}", index, SampleStatusName(record.status));
    const bool pending = record.status == SampleStatus::kPending;
    for (const double u : record.u) row += pending ? std::string(",") : fmt::format(",{}", u);
    // Values as float32, as a results file keeps them: their shortest form reads back exactly.
    for (const double value : record.values) {
      row += pending ? std::string(",") : fmt::format(",{}", static_cast<float>(value));
    }
    fmt::print(out, "{}\n", row);
  }
  return 0;
}

}  // namespace ringtol::jobs
