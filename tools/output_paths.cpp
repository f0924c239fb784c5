#include "output_paths.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include <unistd.h>

#include "sculpt/base/regular_file.hpp"
#include "sculpt/deform/model_io.hpp"

namespace sculpt::tools {
namespace {

namespace fs = std::filesystem;

bool same_file(const std::string& a, const std::string& b) {
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) {
    const bool same = fs::equivalent(a, b, error);
    if (!error) return same;
  }
  const fs::path ca = fs::weakly_canonical(a, error);
  if (error) return false;
  const fs::path cb = fs::weakly_canonical(b, error);
  return !error && ca == cb;
}

bool names_a_file(const std::string& path) { return !path.empty() && path != "-"; }

// The folder `path` would be made in: its nearest ancestor that exists ("." for a bare name).
// The folders below it that are missing are made when the output is written.
fs::path nearest_existing_folder(const fs::path& path) {
  std::error_code error;
  fs::path folder = path.parent_path();
  while (!folder.empty() && !fs::exists(folder, error)) folder = folder.parent_path();
  return folder.empty() ? fs::path(".") : folder;
}

// An existing output that is not a regular file is named for what it is, whatever its
// extension ("/tmp" has none, "shots.png" may be a folder), before the format checks would blame
// the name, and before the work: the atomic writers refuse a FIFO or /dev/null only at the end.
void refuse_non_regular(const NamedPath& output) {
  if (!names_a_file(output.path)) return;
  const std::string kind = base::non_regular_kind(output.path);
  if (kind.empty() || (output.device_allowed && kind == base::kCharacterDevice)) return;
  throw std::invalid_argument(output.what + " " + output.path + " is " + kind + ", not a file to write");
}

void refuse_unusable_folder(const NamedPath& output, const fs::path& folder) {
  std::error_code error;
  if (!fs::is_directory(folder, error)) {
    throw std::invalid_argument(output.what + " " + output.path + ": " + folder.string() +
                                " is not a directory, so nothing can be written under it");
  }
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    throw std::invalid_argument(output.what + " " + output.path + ": the folder " + folder.string() +
                                " is not writable");
  }
}

}  // namespace

void refuse_output_naming_input(const NamedPath& output, std::span<const NamedPath> inputs) {
  if (!names_a_file(output.path)) return;
  for (const NamedPath& input : inputs) {
    if (!names_a_file(input.path) || !same_file(output.path, input.path)) continue;
    throw std::invalid_argument(output.what + " " + output.path + " is " + input.what + " (" + input.path +
                                "): an output may not overwrite an input");
  }
}

void refuse_unwritable_output(const NamedPath& output) {
  if (!names_a_file(output.path)) return;
  refuse_non_regular(output);
  std::error_code error;
  // A device written in place (a log sent to /dev/null) needs no right on its folder.
  const fs::file_status status = fs::status(output.path, error);
  if (!error && fs::is_character_file(status) && ::access(output.path.c_str(), W_OK) == 0) return;
  refuse_unusable_folder(output, nearest_existing_folder(output.path));
}

void refuse_unwritable_folder(const NamedPath& output) {
  if (output.path.empty()) return;
  std::error_code error;
  const bool exists = fs::exists(output.path, error);
  refuse_unusable_folder(output, exists ? fs::path(output.path) : nearest_existing_folder(output.path));
}

void refuse_shared_outputs(std::span<const NamedPath> outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (!names_a_file(outputs[i].path)) continue;
    for (std::size_t j = i + 1; j < outputs.size(); ++j) {
      if (!names_a_file(outputs[j].path) || !same_file(outputs[i].path, outputs[j].path)) continue;
      throw std::invalid_argument(outputs[j].what + " " + outputs[j].path + " is also " + outputs[i].what + " (" +
                                  outputs[i].path +
                                  "): two outputs may not share a file, one would overwrite the other");
    }
  }
}

void check_outputs(std::span<const NamedPath> outputs, std::span<const NamedPath> inputs) {
  for (const NamedPath& output : outputs) {
    refuse_output_naming_input(output, inputs);
    refuse_unwritable_output(output);
  }
  refuse_shared_outputs(outputs);
}

void refuse_overwriting_log(const NamedPath& log, const std::string& replace_flag) {
  if (!names_a_file(log.path)) return;
  std::error_code error;
  const fs::file_status status = fs::status(log.path, error);
  if (error || !fs::is_regular_file(status)) return;  // missing, or not a file: opening it says why
  const std::uintmax_t bytes = fs::file_size(log.path, error);
  if (error || bytes == 0) return;
  throw std::invalid_argument(log.what + " " + log.path + " already holds a session (" + std::to_string(bytes) +
                              " bytes): a new session would erase that edit history; move it, name another "
                              "log, or pass " +
                              replace_flag + " to replace it");
}

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

void refuse_non_png_picture(const std::string& option, const std::string& path) {
  refuse_non_regular({option, path});
  if (lower_extension(path) != ".png") {
    throw std::invalid_argument(option + " " + path + ": the picture is written as PNG; name it .png");
  }
}

void create_parent_folders(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty()) fs::create_directories(parent);
}

void refuse_unwritable_model_format(const std::string& option, const std::string& path) {
  refuse_non_regular({option, path});
  try {
    deform::check_model_format(path);
  } catch (const deform::ModelFileError&) {
    throw std::invalid_argument(option + " " + path +
                                ": cannot write models with that extension (use .ply, .off or .xyz)");
  }
}

}  // namespace sculpt::tools
