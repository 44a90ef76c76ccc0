#include "jobs/cli/pool_run.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "engine/units.h"
#include "jobs/cli/option_flags.h"
#include "jobs/inputs/input_error.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {
namespace {

// The flags that set PoolOptions' fields (jobs/cli/main.cpp, AddPoolOptions and the
// campaign's --test-sample-us); align_samples is the campaign command's own.
constexpr std::array<OptionName, 8> kPoolFlags{{
    {"chunk_samples", "--chunk"},
    {"chunk_seconds", "--chunk-seconds"},
    {"commit_seconds", "--commit-seconds"},
    {"coordinator_computes", "--coordinator-computes"},
    {"threads", "--threads"},
    {"testing.kill_after_committed", "--test-kill-after"},
    {"testing.kill_rank", "--test-kill-rank"},
    {"testing.sample_seconds", "--test-sample-us", units::kSecondsPerMicrosecond},
}};

}  // namespace

std::string Agree(MPI_Comm communicator, const std::string& error) {
  int rank = 0;
  int ranks = 1;
  MPI_Comm_rank(communicator, &rank);
  MPI_Comm_size(communicator, &ranks);
  const int mine = error.empty() ? ranks : rank;
  int first = ranks;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, communicator);
  if (first == ranks) return {};
  std::string message = error;
  int length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, first, communicator);
  message.resize(static_cast<std::size_t>(length));
  MPI_Bcast(message.data(), length, MPI_CHAR, first, communicator);
  return first == 0 ? message : fmt::format("rank {}: {}", first, message);
}

void ThrowAgreed(MPI_Comm communicator, const std::string& error) {
  if (const std::string agreed = Agree(communicator, error); !agreed.empty()) throw InputError(agreed);
}

void SetAsideUnreadable(MPI_Comm communicator, std::ostream& progress,
                        const std::function<std::vector<UnreadableShard>()>& set_aside) {
  int rank = 0;
  MPI_Comm_rank(communicator, &rank);
  ThrowAgreed(communicator, rank == 0 ? Attempt([&] {
    for (const UnreadableShard& shard : set_aside()) {
      fmt::print(progress, "ringtol: {} cannot be read ({}); set aside as {}: its samples are computed again\n",
                 shard.shard.string(), shard.why, shard.aside.string());
    }
  })
                                      : std::string());
}

void CheckBeforeWork(MPI_Comm communicator, const PoolOptions& pool, double progress_seconds,
                     const std::filesystem::path& out, bool resume) {
  int rank = 0;
  MPI_Comm_rank(communicator, &rank);
  ThrowAgreed(communicator, rank == 0 ? Attempt([&] {
    RequireValid(pool, kPoolFlags);
    if (!(progress_seconds > 0.0)) {
      throw InputError(fmt::format("--progress-seconds: {}: out of range; allowed: > 0", progress_seconds));
    }
    CheckOutput(out, resume);
  })
                                      : std::string());
}

void RefuseLiveOutput(const std::filesystem::path& out) {
  if (const std::optional<std::filesystem::path> written = BeingWritten(out)) {
    throw InputError(fmt::format("{}: another ringtol run is writing it ({} is open for writing); let that run finish, "
                                 "or stop it with Ctrl-C or SIGTERM and continue it with --resume, or choose another "
                                 "--out",
                                 out.string(), written->string()));
  }
}

void CheckOutput(const std::filesystem::path& out, bool resume) {
  const std::string name = out.string();
  if (std::filesystem::is_directory(out)) {
    throw InputError(name + ": --out names a folder; name the results file to write, e.g. " +
                     (out / "results.h5").string());
  }
  RefuseLiveOutput(out);
  if (resume) {
    // A run under mpirun killed before it first indexed its shards left only them.
    if (!std::filesystem::exists(out) && FindShards(out).empty())
      throw InputError(name + ": --resume: there is no such results file to continue");
    return;
  }
  if (std::filesystem::exists(out))
    throw InputError(name + ": exists; pass --resume to continue it, or remove it or choose another --out");
  const std::filesystem::path folder = out.parent_path().empty() ? "." : out.parent_path();
  if (!std::filesystem::is_directory(folder))
    throw InputError(name + ": cannot be written: folder " + folder.string() + " does not exist");
  if (access(folder.c_str(), W_OK) != 0)
    throw InputError(name + ": cannot be written: folder " + folder.string() + " is not writable");
}

std::string Clock(double seconds) {
  const auto s = static_cast<long long>(std::llround(seconds));
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60) : fmt::format("{}:{:02}", s / 60, s % 60);
}

std::string ShellWord(const std::string& word) {
  const bool plain = !word.empty() && std::all_of(word.begin(), word.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || std::string_view("_-./=:,+@%").find(c) != std::string_view::npos;
  });
  if (plain) return word;
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

bool UnderLauncher(MPI_Comm communicator) {
  int ranks = 1;
  MPI_Comm_size(communicator, &ranks);
  return ranks > 1 || std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr;
}

std::string ResumeLine(std::vector<std::string> words, int ranks) {
  if (std::find(words.begin(), words.end(), "--resume") == words.end()) words.emplace_back("--resume");
  std::string line = ranks > 1 ? fmt::format("mpirun -n {} ", ranks) : std::string();
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) line += ' ';
    line += ShellWord(words[i]);
  }
  return line;
}

}  // namespace ringtol::jobs
