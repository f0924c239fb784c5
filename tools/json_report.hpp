#pragma once
// The JSON summaries every command writes: the same two stamps in each, and `--json -` for
// scripts that read the summary from a pipe.

#include <nlohmann/json.hpp>

#include <string>

namespace sculpt::tools {

/// The summaries' schema: bumped when a key changes meaning or goes away (new keys do not).
inline constexpr int kJsonSchema = 2;

/// Adds "schema" (kJsonSchema) and "version" (the project version) to a summary.
void stamp_summary(nlohmann::json& summary);

/// For `--json -`: keeps the summary the only thing on stdout, so a script can parse it. The
/// human-readable text printed after this call (printf, std::cout) goes to stderr; write_json
/// still reaches the original stdout. Call once, before anything is printed.
void reserve_stdout_for_json();

/// `summary` as text, indented, with one trailing newline. A byte that is not UTF-8 (a file name
/// or a scene's text, which Linux lets hold any byte) is written as U+FFFD: JSON must be UTF-8,
/// and failing there would lose the summary after all the work.
std::string json_text(const nlohmann::json& summary);

/// Writes `summary` (json_text) to stdout for "-", else atomically to the file
/// (deform::write_file_atomically), making the folders on its way that are still missing (the
/// path was checked by check_outputs before the work).
void write_json(const std::string& path, const nlohmann::json& summary);

}  // namespace sculpt::tools
