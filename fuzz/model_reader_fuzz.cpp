// libFuzzer target: any bytes through one model reader (SCULPT_FUZZ_READER: read_ply_from_buffer,
// read_off_from_buffer or read_xyz_from_buffer). A reader either throws ModelFileError naming
// the buffer, or returns a model that validates, holds finite positions, and reads back the same
// from the PLY the writer makes of it.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include "sculpt/deform/model_io.hpp"

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "model_reader_fuzz: %s\n", what.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sculpt::deform;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  PointModel model;
  try {
    model = SCULPT_FUZZ_READER(bytes, "fuzz-input");
  } catch (const ModelFileError& e) {
    if (e.path() != "fuzz-input") fail(std::string("an error that does not name its input: ") + e.what());
    return 0;
  }
  model.validate();  // throws, and so aborts, when the reader's promise is broken
  for (std::size_t i = 0; i < model.size(); ++i) {
    if (!std::isfinite(model.x[i]) || !std::isfinite(model.y[i]) || !std::isfinite(model.z[i])) {
      fail("a non-finite position at point " + std::to_string(i));
    }
  }
  std::string written;
  try {
    written = write_ply_to_buffer(model);
  } catch (const std::invalid_argument&) {
    return 0;  // normals of any value come as the file has them; the writer refuses non-finite ones
  }
  const PointModel back = read_ply_from_buffer(written, "written");
  if (back.x != model.x || back.y != model.y || back.z != model.z || back.nx != model.nx || back.ny != model.ny ||
      back.nz != model.nz || back.triangles != model.triangles) {
    fail("the model read back from its own PLY differs");
  }
  return 0;
}
