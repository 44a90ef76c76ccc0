// What `ringtol simulate`, `sweep`, `campaign`, `allocate` and `bench campaign` (and
// `bench allocate`) print on stderr before their work when a scene's penalty contact law
// shapes its answer: when the law's compliance changes the ring centre's response to errors
// by more than kContactLawShare against contacts that barely sink
// (solvers/contact_compliance.h, docs/model.md §4). A law the scene file states is the
// user's choice, so a one-line note names the file and keys it came from, the deepest
// contact's penetration and the share; a law from the defaults (the materials') gets a
// warning, naming what to check. Never for rigid contact.
#pragma once

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include "engine/scene.h"

namespace ringtol::jobs {

// The share of the centre's response that a law may change without a word: a change a
// tolerance decision begins to feel. The article's law passes it on its own rig (1.9 %)
// and on a 25 kg steel table (11.6 %); the law of a real material stays a hundred times
// below it (0.006 % and 0.009 %), and a law sinking a table's contacts 34 um does too (0.6 %).
inline constexpr double kContactLawShare = 0.01;

// The message's text, or nothing when the law's share is below kContactLawShare or cannot
// be assessed. `stated_in`: the scene file that states the law, if it does: a note, one
// line starting "ringtol: note: "; otherwise a warning of several lines (each ending in a
// newline, the first starting "ringtol: warning: ").
std::optional<std::string> ContactLawWarning(const engine::Scene& scene,
                                             const std::optional<std::filesystem::path>& stated_in);

// Prints ContactLawWarning(scene, ...), if any, to `warnings`: `scene_file` is the file the
// scene was read from, which StatesContactLaw (jobs/inputs/scene_file.h) reads again.
void WarnAboutContactLaw(const engine::Scene& scene, const std::filesystem::path& scene_file, std::ostream& warnings);

}  // namespace ringtol::jobs
