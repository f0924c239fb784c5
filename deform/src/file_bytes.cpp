#include "file_bytes.hpp"

#include "sculpt/base/regular_file.hpp"
#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform {

std::string read_file_bytes(const std::string& path) {
  try {
    return base::read_regular_file(path);
  } catch (const base::FileReadError& e) {
    throw ModelFileError(path, "", e.what());
  }
}

}  // namespace sculpt::deform
