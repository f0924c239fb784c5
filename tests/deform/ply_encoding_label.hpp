#pragma once
// The name a parameterised PLY test carries for each encoding (its GoogleTest suffix).

#include <string>

#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform::ply_test {

inline std::string encoding_label(PlyEncoding e) {
  switch (e) {
    case PlyEncoding::kAscii: return "Ascii";
    case PlyEncoding::kBinaryLittleEndian: return "LittleEndian";
    case PlyEncoding::kBinaryBigEndian: return "BigEndian";
  }
  return "?";
}

}  // namespace sculpt::deform::ply_test
