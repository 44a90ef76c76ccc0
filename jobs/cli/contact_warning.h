// The warning `ringtol simulate`, `sweep` and `campaign` print on stderr before their work
// when a scene's penalty contact law shapes its answer: when the law's compliance changes
// the ring centre's response to errors by more than kContactLawShare against contacts
// that barely sink (solvers/contact_compliance.h, docs/model.md §4). It names the
// deepest contact's penetration, the law, the penetration the law of the scene's materials
// would give, and what to set. Never for rigid contact.
#pragma once

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

// The warning's text (several lines, each ending in a newline, the first starting
// "ringtol: warning: "), or nothing when the law's share is below kContactLawShare or
// cannot be assessed.
std::optional<std::string> ContactLawWarning(const engine::Scene& scene);

// Prints ContactLawWarning(scene), if any, to `warnings`.
void WarnAboutContactLaw(const engine::Scene& scene, std::ostream& warnings);

}  // namespace ringtol::jobs
