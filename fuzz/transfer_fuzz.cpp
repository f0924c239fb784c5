// libFuzzer target: collision records of any values, plausible or not (NaN, infinities, zero
// or huge radii, negative moduli, frames that lie about their size), transferred onto a small
// sphere frame by frame, each refused frame passed over. transfer() checks each frame before
// any point moves: the model ends finite, and a log whose structure it refuses is left as it was.

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "sculpt/deform/generators.hpp"
#include "sculpt/logging/records.hpp"
#include "sculpt/rt/transfer.hpp"

namespace {

using sculpt::logging::Vec3d;

// Mostly a value within [low, high], sometimes zero, sometimes any 64 bits (NaN, infinity,
// denormals, 1e300).
double value(FuzzedDataProvider& in, double low, double high) {
  switch (in.ConsumeIntegralInRange<int>(0, 7)) {
    case 0: {
      const auto bits = in.ConsumeIntegral<std::uint64_t>();
      double v = 0.0;
      std::memcpy(&v, &bits, sizeof v);
      return v;
    }
    case 1: return 0.0;
    default: return in.ConsumeFloatingPointInRange<double>(low, high);
  }
}

Vec3d vector(FuzzedDataProvider& in, double low, double high) {
  return {value(in, low, high), value(in, low, high), value(in, low, high)};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sculpt;
  FuzzedDataProvider in(data, size);
  std::vector<logging::CollisionRecord> records;
  std::int64_t frame = 0;
  while (in.remaining_bytes() > 0 && records.size() < 40) {
    const int events = in.ConsumeIntegralInRange<int>(1, 6);
    for (int k = 0; k < events; ++k) {
      logging::CollisionRecord r;
      r.frame_id = frame;
      r.frame_size = in.ConsumeBool() ? static_cast<std::uint8_t>(events) : in.ConsumeIntegral<std::uint8_t>();
      r.finger = in.ConsumeIntegralInRange<std::uint8_t>(0, 5);
      r.mode = in.ConsumeBool() ? logging::CollisionMode::kPush : logging::CollisionMode::kPull;
      r.probe = vector(in, -2.0, 2.0);  // the sphere has radius 1
      r.contact = vector(in, -1.2, 1.2);
      r.source = vector(in, -1.5, 1.5);
      r.force = vector(in, -1.0, 1.0);
      r.weights = vector(in, -10.0, 10.0);
      r.effective_force = vector(in, -10.0, 10.0);
      r.bc_radius = value(in, 0.0, 0.5);
      r.region_kind = static_cast<logging::RegionKind>(in.ConsumeIntegralInRange<int>(0, 2));
      r.region_centre = vector(in, -1.5, 1.5);
      r.region_radius = value(in, 0.0, 3.0);
      r.kernel = in.ConsumeBool() ? logging::KernelKind::kKelvin : logging::KernelKind::kRegularized;
      r.kernel_eps = value(in, 0.0, 0.5);
      r.shear_modulus = value(in, 0.0, 10.0);
      r.poisson_ratio = value(in, -1.0, 0.5);
      r.form = in.ConsumeBool() ? logging::ForceForm::kScale : logging::ForceForm::kForce;
      records.push_back(r);
    }
    frame += in.ConsumeIntegralInRange<int>(0, 2);  // 0: the next events join this frame
  }
  static const deform::PointModel kBase = deform::make_sphere(300);
  deform::PointModel model = kBase;
  try {
    rt::transfer(model, records, {}, {}, [](const rt::FrameRejected&) { return true; });
  } catch (const rt::FrameRejected&) {
    if (model.x != kBase.x || model.y != kBase.y || model.z != kBase.z) {
      std::fprintf(stderr, "transfer_fuzz: a refused log moved the model\n");
      std::abort();
    }
  }
  for (std::size_t i = 0; i < model.size(); ++i) {
    const bool finite = std::isfinite(model.x[i]) && std::isfinite(model.y[i]) && std::isfinite(model.z[i]) &&
                        std::isfinite(model.nx[i]) && std::isfinite(model.ny[i]) && std::isfinite(model.nz[i]);
    if (!finite) {
      std::fprintf(stderr, "transfer_fuzz: point %zu is not finite after the transfer\n", i);
      std::abort();
    }
  }
  return 0;
}
