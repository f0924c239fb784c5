#include "sculpt/deform/model_identity.hpp"

#include <bit>
#include <cstdio>
#include <cstring>

namespace sculpt::deform {
namespace {

// The FNV-1a 64 parameters (offset basis and prime) as published by Fowler, Noll and Vo.
constexpr std::uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ull;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

std::uint64_t mix_float(std::uint64_t hash, float value) noexcept {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  for (int byte = 0; byte < 4; ++byte) {  // little-endian whatever the host, so logs travel
    hash ^= (bits >> (8 * byte)) & 0xffu;
    hash *= kFnvPrime;
  }
  return hash;
}

}  // namespace

ModelIdentity model_identity(const PointModel& model) noexcept {
  std::uint64_t hash = kFnvOffsetBasis;
  for (std::size_t i = 0; i < model.size(); ++i) {
    hash = mix_float(hash, model.x[i]);
    hash = mix_float(hash, model.y[i]);
    hash = mix_float(hash, model.z[i]);
  }
  return {model.size(), hash};
}

std::string describe(const ModelIdentity& identity) {
  char text[80];
  std::snprintf(text, sizeof text, "%zu points, hash 0x%016llx", identity.points,
                static_cast<unsigned long long>(identity.hash));
  return text;
}

}  // namespace sculpt::deform
