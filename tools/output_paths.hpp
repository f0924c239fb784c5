#pragma once
// Outputs checked before any work: a session of minutes must not end in "cannot write .obj",
// and no output may overwrite one of the command's own inputs.

#include <span>
#include <string>

namespace sculpt::tools {

/// A path and what the command calls it ("--out", "the log", "the scene's base model").
struct NamedPath {
  std::string what;
  std::string path;
  /// An output that may be a character device: a session's log sent to /dev/null, kept nowhere
  /// on purpose. Every other output is written atomically, which takes regular files only.
  bool device_allowed = false;
};

/// Throws std::invalid_argument ("--out x.ply is the model (--model x.ply); ...") when
/// `output` names the same file as one of `inputs`: the same inode when both exist
/// (std::filesystem::equivalent: hard links, symbolic links, ./ and ../ alike), else the same
/// weakly canonical path. Empty paths and "-" (stdout) name no file and are passed over.
void refuse_output_naming_input(const NamedPath& output, std::span<const NamedPath> inputs);

/// Throws std::invalid_argument when `output` could not be written once the work is done: it is
/// a directory, a FIFO, a socket or a device (a character device passes where `device_allowed`),
/// or the nearest folder on its way that exists is not a directory or not writable (the folders
/// still missing are made when it is written). Empty paths and "-" pass.
void refuse_unwritable_output(const NamedPath& output);

/// The same for an output folder (sculpt report --out): an existing path must be a writable
/// directory, a missing one must have one as its nearest existing ancestor.
void refuse_unwritable_folder(const NamedPath& output);

/// Throws std::invalid_argument ("--json a.ply is also --out (a.ply): ...") when two of
/// `outputs` name the same file, judged as refuse_output_naming_input judges: a session's JSON
/// written over its model or its log would lose them after all the work.
void refuse_shared_outputs(std::span<const NamedPath> outputs);

/// The three checks above for a command's outputs, before any work: none names one of `inputs`,
/// each could be written, and no two share a file. The first problem found is thrown.
void check_outputs(std::span<const NamedPath> outputs, std::span<const NamedPath> inputs);

/// Throws std::invalid_argument naming `option` when `path` is a directory or anything else
/// that is not a regular file (whatever its extension), or is not .ply, .off or .xyz (what
/// deform::write_model writes).
void refuse_unwritable_model_format(const std::string& option, const std::string& path);

/// Throws std::invalid_argument when `log` names a file that exists and holds anything: an event
/// log is a session's edit history (base model + log = the sculpted model), and a new session
/// opening it would truncate it. The message names the file, its size, and `replace_flag`, the
/// option that says the old session may go. A missing or empty file passes.
void refuse_overwriting_log(const NamedPath& log, const std::string& replace_flag);

/// Throws std::invalid_argument naming `option` when `path` is a directory or anything else
/// that is not a regular file, or is not named .png (what render::write_png writes).
void refuse_non_png_picture(const std::string& option, const std::string& path);

/// Makes the folders on `path`'s way that are still missing, as an output checked by
/// refuse_unwritable_output is about to be written. A path without a folder needs none.
/// @throw std::filesystem::filesystem_error when one cannot be made.
void create_parent_folders(const std::string& path);

/// The path's extension in lower case, with its dot (".ply"); empty when it has none.
std::string lower_extension(const std::string& path);

}  // namespace sculpt::tools
