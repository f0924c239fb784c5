#pragma once
// Reading and writing point models: PLY (all three encodings), OFF and XYZ.
//
// Every reader loads the whole file into memory and parses it from there, so the in-memory
// *_from_buffer variants behave exactly like the file ones (the tests and fuzzers use them).
// Only regular files are read (a directory, FIFO or device is refused before any read), and
// every count a header declares is checked against the bytes left before anything is allocated
// for it. Readers either return a model that passes PointModel::validate() or throw
// ModelFileError. Normals come as the file has them (zero, non-finite or of any length):
// check_normals() (normal_check.hpp) is what makes them unit normals or refuses them.
//
// Every writer builds the whole file in memory and hands it to write_file_atomically(), so a
// failed write leaves the old file in place. Faces are written by PLY and OFF.

#include <stdexcept>
#include <string>
#include <string_view>

#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

/// The three PLY body encodings.
enum class PlyEncoding { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

/// Thrown for any model file that cannot be opened, read or written, or is malformed.
/// what() is "<path>: <where>: <problem>", where <where> is "line N" (1-based) for text
/// (PLY header, PLY ascii body, OFF, XYZ) or "byte offset N" (from the start of the file) for
/// binary PLY bodies. Errors that concern the whole file (cannot open it, unknown extension)
/// have an empty <where> and read "<path>: <problem>".
class ModelFileError : public std::runtime_error {
 public:
  ModelFileError(std::string path, std::string where, std::string problem);

  /// The file (or buffer name) the error is about.
  const std::string& path() const { return path_; }
  /// "line N", "byte offset N" or empty.
  const std::string& where() const { return where_; }
  /// What is wrong, without the path and position.
  const std::string& problem() const { return problem_; }

 private:
  std::string path_;
  std::string where_;
  std::string problem_;
};

/// Reads a PLY file in any encoding. Vertex properties x, y, z (required), nx, ny, nz and
/// red, green, blue, alpha may come in any order and any PLY numeric type; all other
/// properties and elements are skipped. A "face" element's vertex_indices (or vertex_index)
/// list becomes PointModel::triangles, polygons fanned.
PointModel read_ply(const std::string& path);
/// read_ply on bytes already in memory; `name_for_errors` stands in for the path in errors.
PointModel read_ply_from_buffer(std::string_view bytes, const std::string& name_for_errors);

/// Writes positions (float), normals (float), colours (uchar) when present, and the triangles as
/// a "face" element (property list uchar int vertex_indices) when the model has any.
/// Throws std::invalid_argument when the model is inconsistent (see PointModel::validate) or
/// has non-finite normals, and ModelFileError when the file cannot be written.
void write_ply(const std::string& path, const PointModel& model,
               PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian);
/// write_ply into a byte string instead of a file.
std::string write_ply_to_buffer(const PointModel& model, PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian);

/// Reads an OFF file (also NOFF, COFF, CNOFF and STOFF variants): vertices, and faces fanned
/// into triangles. '#' starts a comment.
PointModel read_off(const std::string& path);
/// read_off on text already in memory.
PointModel read_off_from_buffer(std::string_view text, const std::string& name_for_errors);

/// Writes OFF, NOFF, COFF or CNOFF as the model has normals and colours: "x y z [nx ny nz]
/// [r g b a]" per vertex (alpha 255 when the model has none; read_off drops alpha), then one
/// "3 a b c" line per triangle. Throws like write_ply.
void write_off(const std::string& path, const PointModel& model);
/// write_off into a string instead of a file.
std::string write_off_to_buffer(const PointModel& model);

/// Reads an XYZ point file: "x y z" or "x y z nx ny nz" per line (the same on every line),
/// '#' comments and blank lines allowed.
PointModel read_xyz(const std::string& path);
/// read_xyz on text already in memory.
PointModel read_xyz_from_buffer(std::string_view text, const std::string& name_for_errors);

/// Writes "x y z" (or "x y z nx ny nz" when the model has normals) per line, with the
/// shortest digits that read back to the same floats. Colours and faces are not written.
void write_xyz(const std::string& path, const PointModel& model);
/// write_xyz into a string instead of a file.
std::string write_xyz_to_buffer(const PointModel& model);

/// Reads by file extension, case-insensitively: .ply, .off or .xyz. Any other extension
/// throws ModelFileError.
PointModel read_model(const std::string& path);
/// Throws the ModelFileError write_model would throw for a path whose extension it cannot
/// write, so a command can refuse an output before any work rather than after it.
void check_model_format(const std::string& path);
/// Writes by file extension, case-insensitively: .ply (with `encoding`), .off or .xyz. Any
/// other extension throws ModelFileError.
void write_model(const std::string& path, const PointModel& model,
                 PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian);

}  // namespace sculpt::deform
