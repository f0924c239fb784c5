#pragma once
// The deformation guards that acted, as every command reports them: one text for the tables
// and summaries (sculpt check, sculpt deform), one JSON object for the summaries (check,
// deform, run), so that a guard added to deform::for_each_guard shows everywhere at once.

#include <nlohmann/json_fwd.hpp>

#include <string>

#include "sculpt/deform/deformer.hpp"

namespace sculpt::tools {

/// Each guard whose count is not zero as " <name><separator><count>", in for_each_guard's
/// order (" fold_splits=2 damped=1" with '='); empty when none acted.
std::string acted_guards(const deform::GuardCounts& guards, char separator);

/// {"<name>": count, ...} over every guard, zeros included.
nlohmann::json guards_json(const deform::GuardCounts& guards);

}  // namespace sculpt::tools
