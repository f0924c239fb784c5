// ModelFileError, and choosing a reader or writer by file extension.

#include "sculpt/deform/model_io.hpp"

#include <cctype>
#include <filesystem>
#include <string>

namespace sculpt::deform {
namespace {

std::string message(const std::string& path, const std::string& where, const std::string& problem) {
  return where.empty() ? path + ": " + problem : path + ": " + where + ": " + problem;
}

// ".PLY" and ".ply" alike; empty when the name has no extension.
std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string shown_extension(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext.empty() ? "no extension" : "extension '" + ext + "'";
}

}  // namespace

ModelFileError::ModelFileError(std::string path, std::string where, std::string problem)
    : std::runtime_error(message(path, where, problem)),
      path_(std::move(path)),
      where_(std::move(where)),
      problem_(std::move(problem)) {}

PointModel read_model(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return read_ply(path);
  if (ext == ".off") return read_off(path);
  if (ext == ".xyz") return read_xyz(path);
  throw ModelFileError(path, "", "cannot read models with " + shown_extension(path) + " (use .ply, .off or .xyz)");
}

void check_model_format(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply" || ext == ".off" || ext == ".xyz") return;
  throw ModelFileError(path, "", "cannot write models with " + shown_extension(path) + " (use .ply, .off or .xyz)");
}

void write_model(const std::string& path, const PointModel& model, PlyEncoding encoding) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply") {
    write_ply(path, model, encoding);
  } else if (ext == ".off") {
    write_off(path, model);
  } else if (ext == ".xyz") {
    write_xyz(path, model);
  } else {
    check_model_format(path);
  }
}

}  // namespace sculpt::deform
