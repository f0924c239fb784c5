// Writes the log fuzzer's seed: a short checked session as the station writes one (a session
// header, two fingers pressing a 300-point sphere for four frames, their collision records, a
// tick a frame, a flush after each frame), so that mutations start from every kind of event.
//
//   make_log_seed OUT.lcmlog

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/logging/durable_log.hpp"
#include "sculpt/rt/transfer.hpp"

int main(int argc, char** argv) {
  using namespace sculpt;
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_log_seed OUT.lcmlog\n");
    return 2;
  }
  try {
    logging::DurableLogConfig config;
    config.path = argv[1];
    logging::DurableLog log(config);
    sculpt_lcm::session_header_t header{};
    header.schema = sculpt_lcm::session_header_t::SCHEMA;
    header.version = "make_log_seed";
    header.scene_path = "seed.toml";
    header.scene_text = "[model]\npath = \"sphere.ply\"\n";
    header.model_points = 300;
    header.reduced_ratio = 1.0;
    header.full_points = 300;
    log.write_session_header(header);

    deform::PointModel model = deform::make_sphere(300);
    deform::DeformSettings settings;
    settings.contact.bc_radius = 0.2;
    settings.contact.min_source_distance = 0.05;
    settings.contact.guard_distance = 0.3;
    deform::Deformer deformer(model, settings);
    const std::size_t fingers[2] = {0, 150};
    std::int64_t frame_id = 0;
    for (int frame = 1; frame <= 4; ++frame) {
      std::vector<deform::ProbeMotion> probes;
      for (const std::size_t i : fingers) {
        const deform::Vec3 a = model.position(i), n = model.normal(i);
        probes.push_back({a + n * 0.1, a - n * (0.02 * frame), std::nullopt});
      }
      const std::int64_t utime = 1'700'000'000'000'000 + frame * 1000;
      std::vector<logging::CollisionRecord> records;
      deformer.deform(probes);
      for (const deform::FrameReport& step : deformer.frames()) {  // a frame split into substeps: one each
        rt::append_frame_records(step, settings, frame_id++, frame, records);
      }
      for (logging::CollisionRecord& r : records) {
        r.utime = utime;
        log.record(r);
      }
      logging::TickRecord tick;
      tick.utime = utime;
      tick.tick = frame;
      tick.collisions = static_cast<std::int16_t>(records.size());
      log.record(tick);
      log.flush_now();
    }
    log.stop();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_log_seed: %s\n", e.what());
    return 1;
  }
  return 0;
}
