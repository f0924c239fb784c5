#include "sculpt/rt/scene.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>

#include "scene_reader.hpp"
#include "sculpt/base/regular_file.hpp"
#include "sculpt/base/time_limits.hpp"
#include "sculpt/rt/transport_url.hpp"

namespace sculpt::rt {

namespace {

using scene_detail::as_number;
using scene_detail::as_vec3;
using scene_detail::Context;
using scene_detail::one_of;
using scene_detail::Section;
using scene_detail::show;
using scene_detail::type_name;

// Every time, timeout and rate is bounded above as well as below: past these a value is a typo,
// and past int64 nanoseconds (a 1e13 ms timeout added to a clock) it stops a session at once or
// makes a hand always stale.
constexpr const char* kTimeoutNote = "milliseconds: at most an hour";
constexpr const char* kDurationNote = "seconds: at most a year";
/// One Euro cutoffs above this pass everything the 2 kHz loop can sample: no filter at all.
constexpr double kMaxCutoffHz = 1e4;
/// Fastest rise of a haptic force: the largest force allowed (1000 N) in a millisecond.
constexpr double kMaxForceRate = 1e6;

/// A timeout, interval or latency in milliseconds: in (0, an hour], or [0, an hour] when
/// `zero_allowed`.
std::optional<double> timeout_ms(const Section& s, std::string_view key, bool zero_allowed = false) {
  return s.number_in(key, 0.0, !zero_allowed, base::kMaxTimeoutMs, false, kTimeoutNote);
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// A path key: non-empty, resolved against the scene's directory when relative.
std::optional<std::string> path_value(const Section& s, std::string_view key, const std::string& base_dir) {
  auto text = s.string(key);
  if (!text) return text;
  s.check(!text->empty(), key, "must not be empty");
  std::filesystem::path p(*text);
  if (p.is_relative() && !base_dir.empty()) p = std::filesystem::path(base_dir) / p;
  return p.lexically_normal().string();
}

void read_model(const Section& root, const std::string& base_dir, Scene& scene) {
  const Section s = root.table("model", {"path", "reference", "normals", "bad_normals"});
  s.require("path");
  scene.model.path = *path_value(s, "path", base_dir);
  const std::string ext = lower_extension(scene.model.path);
  s.check(ext == ".ply" || ext == ".off" || ext == ".xyz", "path",
          "unsupported model format '" + ext + "'; expected .ply, .off or .xyz");

  scene.model.reference = s.vec3("reference");
  const auto normals = s.choice<NormalsSource>("normals", {{"auto", NormalsSource::kAuto},
                                                           {"faces", NormalsSource::kFaces},
                                                           {"pca", NormalsSource::kPca},
                                                           {"none", NormalsSource::kNone}});
  // A reference point replaces normals (the thesis's test); naming both would leave one unused.
  scene.model.normals = normals.value_or(scene.model.reference ? NormalsSource::kNone : NormalsSource::kAuto);
  if (scene.model.reference && scene.model.normals != NormalsSource::kNone) {
    s.fail("reference", "only used with model.normals = 'none' (a reference point replaces normals)");
  }
  if (!scene.model.reference && scene.model.normals == NormalsSource::kNone) {
    s.fail("normals", "'none' needs model.reference, a point outside the model, to tell inside from outside");
  }
  const auto bad_normals = s.choice<deform::NormalPolicy>(
      "bad_normals", {{"reestimate", deform::NormalPolicy::kReestimate}, {"refuse", deform::NormalPolicy::kRefuse}});
  // The other normals choices replace the file's normals, so a policy for them would go unused.
  if (bad_normals && scene.model.normals != NormalsSource::kAuto) {
    s.fail("bad_normals", "only used with model.normals = 'auto' (the other choices replace the file's normals)");
  }
  scene.model.bad_normals = bad_normals.value_or(deform::NormalPolicy::kReestimate);
}

void read_material_and_kernel(const Section& root, Scene& scene) {
  const Section m = root.table("material", {"G", "nu"});
  if (const auto g = m.positive("G")) {
    m.check(*g <= deform::kMaxShearModulus, "G", "out of range: " + show(*g) + " is above 1e15");
    m.check(*g >= deform::kMinShearModulus, "G", "out of range: " + show(*g) + " is below 1e-15");
    scene.material.shear_modulus = *g;
  }
  scene.material.poisson_ratio = m.number_in("nu", -1.0, true, 0.5, false).value_or(scene.material.poisson_ratio);

  const Section k = root.table("kernel", {"kind", "eps"});
  scene.kernel.kind = k.choice<deform::KernelKind>("kind", {{"kelvin", deform::KernelKind::kKelvin},
                                                            {"regularized", deform::KernelKind::kRegularized}})
                          .value_or(deform::KernelKind::kKelvin);
  const auto eps = k.positive("eps");
  if (scene.kernel.kind == deform::KernelKind::kRegularized) {
    if (!eps) {
      scene_detail::fail(k.context(), k.where("kind"), k.key("eps"),
                         "missing required key (kernel.kind is 'regularized')");
    }
    scene.kernel.eps = *eps;
  } else if (eps) {
    k.fail("eps", "only used with kernel.kind = 'regularized'");
  }
}

void read_heuristic(const Section& root, Scene& scene) {
  const Section s = root.table("heuristic", {"region", "budget_fraction", "reduced_ratio", "strict_region"});
  auto& h = scene.heuristic;
  if (const toml::node* region = s.node("region")) {
    if (region->is_string()) {
      const std::string text = region->as_string()->get();
      if (text == "global") {
        h.region = RegionChoice::kGlobal;
      } else if (text == "auto") {
        h.region = RegionChoice::kAuto;
      } else {
        s.fail("region", "unknown value '" + text + "'; expected 'global', 'auto' or a radius");
      }
    } else if (region->is_number()) {
      h.region = RegionChoice::kRadius;
      h.region_radius = *s.positive("region");
    } else {
      s.fail("region", "expected 'global', 'auto' or a radius (number), got " + std::string(type_name(*region)));
    }
  }
  h.budget_fraction = s.number_in("budget_fraction", 0.0, true, 1.0, false).value_or(h.budget_fraction);
  h.reduced_ratio = s.number_in("reduced_ratio", 0.0, true, 1.0, false).value_or(h.reduced_ratio);
  if (const auto strict = s.boolean("strict_region")) {
    if (h.region == RegionChoice::kGlobal) {
      s.fail("strict_region", "only used with a localised region (heuristic.region is 'global')");
    }
    h.strict_region = *strict;
  }
}

void read_deform(const Section& root, Scene& scene) {
  const Section s =
      root.table("deform", {"form", "mode", "bc_radius", "delta_s", "delta_d", "delta_r", "precision", "carry_normals",
                            "normal_skip_bound", "fast_inverse_sqrt", "border_weight", "max_patch_points", "threads"});
  auto& d = scene.deform;
  d.form = s.choice<deform::WeightForm>("form",
                                        {{"scale", deform::WeightForm::kScale}, {"force", deform::WeightForm::kForce}})
               .value_or(d.form);
  d.mode = s.choice<deform::ContactMode>("mode",
                                         {{"push", deform::ContactMode::kPush}, {"pull", deform::ContactMode::kPull}})
               .value_or(d.mode);
  d.bc_radius = s.positive("bc_radius");
  d.delta_s = s.non_negative("delta_s");
  d.delta_d = s.positive("delta_d");
  d.delta_r = s.non_negative("delta_r");
  if (const auto cap = s.integer_in("max_patch_points", 1, static_cast<std::int64_t>(deform::kMaxPatchPointsLimit))) {
    d.max_patch_points = static_cast<std::size_t>(*cap);
  }
  if (const auto threads = s.integer_in("threads", 1, 2)) d.threads = static_cast<int>(*threads);
  d.precision = s.choice<deform::Precision>(
                     "precision", {{"float", deform::Precision::kFloat}, {"double", deform::Precision::kDouble}})
                    .value_or(d.precision);
  if (const auto carry = s.boolean("carry_normals")) {
    if (scene.model.normals == NormalsSource::kNone && *carry) {
      s.fail("carry_normals", "the model has no normals (model.normals is 'none')");
    }
    d.carry_normals = *carry;
  }
  d.normal_skip_bound =
      s.number_in("normal_skip_bound", 0.0, false, deform::kMaxNormalSkipBound, false).value_or(d.normal_skip_bound);
  if (const auto fast = s.boolean("fast_inverse_sqrt")) {
    if (*fast && d.precision == deform::Precision::kDouble) {
      s.fail("fast_inverse_sqrt", "only the float loop has it (deform.precision is 'double')");
    }
    d.fast_inverse_sqrt = *fast;
  }
  if (const auto weight = s.non_negative("border_weight")) {
    if (scene.heuristic.region == RegionChoice::kGlobal) {
      s.fail("border_weight", "only used with a localised region (heuristic.region is 'global')");
    }
    d.border_weight = *weight;
  }
}

constexpr std::array<std::string_view, hal::kFingers> kFingerNames = {"thumb", "index", "middle", "ring", "little"};

/// A finger as the scene spells it: "'index'".
std::string finger_name(std::uint8_t finger) {
  return finger < kFingerNames.size() ? "'" + std::string(kFingerNames[finger]) + "'" : std::to_string(finger);
}
std::string hand_name(std::uint8_t hand) { return std::to_string(hand); }

/// "[0, 1]", "['index', 'middle']": a hand or finger list as the scene spells it.
std::string id_names(const std::vector<std::uint8_t>& ids, std::string (*name)(std::uint8_t)) {
  std::string text = "[";
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (i > 0) text += ", ";
    text += name(ids[i]);
  }
  return text + "]";
}

std::uint8_t finger_number(const Context& context, const toml::node& node, const std::string& key) {
  if (const auto* name = node.as_string()) {
    for (std::size_t f = 0; f < kFingerNames.size(); ++f) {
      if (name->get() == kFingerNames[f]) return static_cast<std::uint8_t>(f);
    }
    scene_detail::fail(context, node.source().begin, key,
                       "unknown finger '" + name->get() + "'; expected " +
                           one_of({"thumb", "index", "middle", "ring", "little"}) + ", or 0..4");
  }
  if (const auto* number = node.as_integer()) {
    if (number->get() < 0 || number->get() >= static_cast<std::int64_t>(hal::kFingers)) {
      scene_detail::fail(context, node.source().begin, key,
                         "finger " + std::to_string(number->get()) + " is not in 0..4");
    }
    return static_cast<std::uint8_t>(number->get());
  }
  scene_detail::fail(context, node.source().begin, key,
                     "expected a finger name or 0..4, got " + std::string(type_name(node)));
}

std::uint8_t hand_number(const Context& context, const toml::node& node, const std::string& key) {
  const auto* number = node.as_integer();
  if (number == nullptr) {
    scene_detail::fail(context, node.source().begin, key,
                       "expected a hand, 0 or 1, got " + std::string(type_name(node)));
  }
  if (number->get() < 0 || number->get() >= static_cast<std::int64_t>(hal::kHands)) {
    scene_detail::fail(context, node.source().begin, key, "hand " + std::to_string(number->get()) + " is not 0 or 1");
  }
  return static_cast<std::uint8_t>(number->get());
}

/// A list of hands or fingers: non-empty, no repeats; returned ascending.
template <typename Parse>
std::optional<std::vector<std::uint8_t>> id_list(const Section& s, std::string_view key, Parse parse) {
  const toml::array* array = s.array(key);
  if (array == nullptr) return std::nullopt;
  s.check(!array->empty(), key, "must not be empty");
  std::vector<std::uint8_t> ids;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::string element = s.key(key) + "[" + std::to_string(i) + "]";
    const std::uint8_t id = parse(s.context(), *array->get(i), element);
    if (std::find(ids.begin(), ids.end(), id) != ids.end()) {
      scene_detail::fail(s.context(), array->get(i)->source().begin, element, "listed twice");
    }
    ids.push_back(id);
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

void read_script(const Section& s, hal::FingerScript& script) {
  s.allow({"hand", "finger", "keyframes"});
  if (const toml::node* hand = s.node("hand")) script.hand = hand_number(s.context(), *hand, s.key("hand"));
  s.require("finger");
  script.finger = finger_number(s.context(), *s.node("finger"), s.key("finger"));
  s.require("keyframes");
  const toml::array* frames = s.array("keyframes");
  s.check(!frames->empty(), "keyframes", "must not be empty");
  for (std::size_t i = 0; i < frames->size(); ++i) {
    const toml::node& frame = *frames->get(i);
    const std::string key = s.key("keyframes") + "[" + std::to_string(i) + "]";
    const toml::array* values = frame.as_array();
    if (values == nullptr || values->size() != 4) {
      scene_detail::fail(
          s.context(), frame.source().begin, key,
          "expected [t, x, y, z], got " +
              (values == nullptr ? std::string(type_name(frame)) : std::to_string(values->size()) + " elements"));
    }
    double v[4];
    for (std::size_t j = 0; j < 4; ++j) {
      v[j] = as_number(s.context(), *values->get(j), key + "[" + std::to_string(j) + "]");
    }
    if (v[0] < 0.0) {
      scene_detail::fail(s.context(), frame.source().begin, key, "time " + show(v[0]) + " s is negative");
    }
    if (v[0] > base::kMaxDurationS) {
      scene_detail::fail(s.context(), frame.source().begin, key,
                         "time " + show(v[0]) + " s is beyond a year (" + show(base::kMaxDurationS) + " s)");
    }
    // The simulator interpolates between neighbours; equal or falling times have no meaning.
    if (!script.keyframes.empty() && !(v[0] > script.keyframes.back().time_s)) {
      scene_detail::fail(s.context(), frame.source().begin, key,
                         "time " + show(v[0]) + " s is not after the previous keyframe's " +
                             show(script.keyframes.back().time_s) + " s");
    }
    script.keyframes.push_back({v[0], v[1], v[2], v[3]});
  }
}

/// Where each script of glove.sim names its hand and finger, for messages about the script.
struct ScriptPlace {
  std::string key;               ///< "glove.sim.script[1]"
  toml::source_position hand;    ///< its hand key, or the script's table when the hand is implied
  toml::source_position finger;  ///< its finger key
};

void read_sim(const Section& s, hal::SimConfig& sim, std::vector<ScriptPlace>& places) {
  sim.rate_hz = s.number_in("rate_hz", 1.0, false, 2000.0, false).value_or(sim.rate_hz);
  if (const auto seed = s.integer_in("seed", 0, std::numeric_limits<std::int64_t>::max())) {
    sim.seed = static_cast<std::uint64_t>(*seed);
  }
  sim.jitter_stddev = s.non_negative("jitter").value_or(sim.jitter_stddev);
  sim.dropout_probability = s.number_in("dropout", 0.0, false, 1.0, true).value_or(sim.dropout_probability);
  sim.latency_ms = timeout_ms(s, "latency_ms", true).value_or(sim.latency_ms);
  sim.repeat = s.boolean("repeat").value_or(sim.repeat);
  sim.duration_s =
      s.number_in("duration_s", 0.0, false, base::kMaxDurationS, false, kDurationNote).value_or(sim.duration_s);

  s.require("script", "a [[glove.sim.script]] per finger that moves");
  const toml::array* scripts = s.array("script");
  s.check(!scripts->empty(), "script", "must not be empty");
  for (std::size_t i = 0; i < scripts->size(); ++i) {
    const toml::node& node = *scripts->get(i);
    const std::string key = s.key("script") + "[" + std::to_string(i) + "]";
    const toml::table* table = node.as_table();
    if (table == nullptr) {
      scene_detail::fail(s.context(), node.source().begin, key,
                         "expected a table, got " + std::string(type_name(node)));
    }
    hal::FingerScript script;
    const Section script_section(s.context(), table, key, node.source().begin);
    read_script(script_section, script);
    places.push_back({key, script_section.where("hand"), script_section.where("finger")});
    for (const auto& other : sim.fingers) {
      if (other.hand == script.hand && other.finger == script.finger) {
        scene_detail::fail(s.context(), node.source().begin, key,
                           "hand " + std::to_string(script.hand) + " finger " + std::to_string(script.finger) +
                               " already has a script");
      }
    }
    sim.fingers.push_back(std::move(script));
  }
}

void read_serial(const Section& s, hal::SerialConfig& serial) {
  s.require("device");
  serial.device = *s.string("device");
  s.check(!serial.device.empty(), "device", "must not be empty");
  if (const auto baud = s.integer_in("baud", 1, 100'000'000)) serial.baud = static_cast<int>(*baud);
  serial.reconnect_interval_ms = timeout_ms(s, "reconnect_ms").value_or(serial.reconnect_interval_ms);
}

void read_lcm_transport(const Section& s, const std::string& default_url, std::string& url, std::string& channel) {
  url = s.string("url").value_or(default_url);
  if (const std::string problem = lcm_url_problem(url); !problem.empty()) s.fail("url", problem);
  if (const auto c = s.string("channel")) {
    if (const std::string problem = lcm_channel_problem(*c); !problem.empty()) s.fail("channel", problem);
    channel = *c;
  }
}

void read_can(const Section& s, hal::CanConfig& can) {
  if (const auto name = s.string("interface")) {
    // Linux interface names are at most IFNAMSIZ - 1 = 15 bytes.
    s.check(!name->empty() && name->size() <= 15, "interface",
            "'" + *name + "' is not a network interface name (1 to 15 characters)");
    can.interface = *name;
  }
  can.fd = s.boolean("fd").value_or(can.fd);
  // The glove uses ids base_id .. base_id + 0x81 (docs/glove-can.md); all must fit 29 bits.
  if (const auto id = s.integer_in("base_id", 0, 0x1FFFFFFF - 0x81)) can.base_id = static_cast<std::uint32_t>(*id);
}

void read_usb(const Section& s, hal::UsbConfig& usb) {
  s.require("vendor_id");
  usb.vendor_id = static_cast<std::uint16_t>(*s.integer_in("vendor_id", 1, 0xFFFF));
  s.require("product_id");
  usb.product_id = static_cast<std::uint16_t>(*s.integer_in("product_id", 0, 0xFFFF));
  if (const auto i = s.integer_in("interface", 0, 255)) usb.interface_number = static_cast<int>(*i);
  // Bit 7 of an endpoint address is its direction: set for IN, clear for OUT.
  if (const auto e = s.integer_in("endpoint", 0x81, 0x8F)) usb.endpoint = static_cast<std::uint8_t>(*e);
  if (const auto e = s.integer_in("out_endpoint", 0x01, 0x0F)) usb.out_endpoint = static_cast<std::uint8_t>(*e);
  usb.transfer = s.choice<hal::UsbConfig::Transfer>("transfer", {{"interrupt", hal::UsbConfig::Transfer::kInterrupt},
                                                                 {"bulk", hal::UsbConfig::Transfer::kBulk}})
                     .value_or(usb.transfer);
}

struct SectionKeys {
  std::string_view name;
  std::initializer_list<std::string_view> keys;
};

/// A backend's section must be there when it is chosen, and no other backend's may be: a scene
/// names only what it uses, so a leftover section is a mistake to point at, not to ignore.
void check_backend_sections(const Section& s, std::string_view selector, std::string_view chosen,
                            std::initializer_list<std::string_view> sections) {
  for (const auto name : sections) {
    if (name == chosen) {
      if (!s.has(name)) {
        // The simulator's section comes into being with its first script.
        const std::string add_hint = name == "sim" ? "[[" + s.key(name) + ".script]]" : "[" + s.key(name) + "]";
        scene_detail::fail(
            s.context(), s.where(selector), s.key(name),
            s.key(selector) + " is '" + std::string(chosen) + "' but this section is missing; add " + add_hint);
      }
    } else if (s.has(name)) {
      s.fail(name, std::string(selector) + " is '" + std::string(chosen) + "'; remove this section or change " +
                       s.key(selector));
    }
  }
}

void read_glove(const Section& root, Scene& scene) {
  const Section s = root.table("glove", {"backend", "timeout_ms", "queue_capacity", "hands", "fingers", "sim", "serial",
                                         "usb", "lcm", "socketcan"});
  auto& glove = scene.glove;
  auto& config = glove.config;
  s.require("backend");
  const std::string backend = *s.string("backend");
  config.backend = *s.choice<hal::Backend>("backend", {{"sim", hal::Backend::kSim},
                                                       {"serial", hal::Backend::kSerial},
                                                       {"usb", hal::Backend::kUsb},
                                                       {"lcm", hal::Backend::kLcm},
                                                       {"socketcan", hal::Backend::kSocketCan}});
  check_backend_sections(s, "backend", backend, {"sim", "serial", "usb", "lcm", "socketcan"});
  std::vector<ScriptPlace> script_places;
  glove.timeout_ms = timeout_ms(s, "timeout_ms").value_or(glove.timeout_ms);
  if (const auto q = s.integer_in("queue_capacity", 2, 1 << 20)) config.queue_capacity = static_cast<std::size_t>(*q);

  switch (config.backend) {
    case hal::Backend::kSim:
      read_sim(s.table("sim", {"rate_hz", "seed", "jitter", "dropout", "latency_ms", "repeat", "duration_s", "script"}),
               config.sim, script_places);
      break;
    case hal::Backend::kSerial:
      read_serial(s.table("serial", {"device", "baud", "reconnect_ms"}), config.serial);
      break;
    case hal::Backend::kUsb: {
      const Section usb =
          s.table("usb", {"vendor_id", "product_id", "interface", "endpoint", "out_endpoint", "transfer"});
      // Known, so that the message can say where it belongs: the source only reads.
      if (usb.has("out_endpoint")) {
        usb.fail("out_endpoint",
                 "the glove source only reads its IN endpoint; the OUT endpoint for haptic frames "
                 "is [haptic.usb] out_endpoint");
      }
      read_usb(usb, config.usb);
      break;
    }
    case hal::Backend::kLcm:
      read_lcm_transport(s.table("lcm", {"url", "channel"}), scene.lcm.url, config.lcm.url, config.lcm.glove_channel);
      break;
    case hal::Backend::kSocketCan: read_can(s.table("socketcan", {"interface", "fd", "base_id"}), config.can); break;
  }

  // Unlisted, the acting hands and fingers are the scripted ones for the simulator (the others
  // send nothing), and one right hand's five fingers for a real glove.
  const auto hands = id_list(s, "hands", hand_number);
  const auto fingers = id_list(s, "fingers", finger_number);
  if (hands) {
    glove.hands = *hands;
  } else if (config.backend == hal::Backend::kSim) {
    for (const auto& f : config.sim.fingers) glove.hands.push_back(f.hand);
  } else {
    glove.hands = {0};
  }
  if (fingers) {
    glove.fingers = *fingers;
  } else if (config.backend == hal::Backend::kSim) {
    for (const auto& f : config.sim.fingers) glove.fingers.push_back(f.finger);
  } else {
    glove.fingers = {0, 1, 2, 3, 4};
  }
  for (auto* list : {&glove.hands, &glove.fingers}) {
    std::sort(list->begin(), list->end());
    list->erase(std::unique(list->begin(), list->end()), list->end());
  }
  // The acting fingers are glove.hands x glove.fingers. A script for any other finger would
  // move a fingertip nothing reads: the scene's author meant it to press, so it is a mistake.
  const auto has = [](const std::vector<std::uint8_t>& list, std::uint8_t id) {
    return std::find(list.begin(), list.end(), id) != list.end();
  };
  for (std::size_t i = 0; i < script_places.size(); ++i) {
    const hal::FingerScript& script = config.sim.fingers[i];
    const bool hand_acts = has(glove.hands, script.hand);
    if (hand_acts && has(glove.fingers, script.finger)) continue;
    const std::string what = "hand " + hand_name(script.hand) + " finger " + finger_name(script.finger);
    const std::string problem = hand_acts
                                    ? what + " does not act: glove.fingers is " + id_names(glove.fingers, finger_name) +
                                          "; add it there or remove this script"
                                    : what + " does not act: glove.hands is " + id_names(glove.hands, hand_name) +
                                          "; add it there or remove this script";
    const ScriptPlace& place = script_places[i];
    scene_detail::fail(s.context(), hand_acts ? place.finger : place.hand, place.key, problem);
  }
}

void read_hand(const Section& root, Scene& scene) {
  const Section s = root.table("hand", {"kind", "bone_lengths"});
  scene.hand.kind = s.choice<hal::SampleKind>(
                         "kind", {{"positions", hal::SampleKind::kPositions}, {"angles", hal::SampleKind::kAngles}})
                        .value_or(hal::SampleKind::kPositions);
  if (scene.hand.kind == hal::SampleKind::kAngles && scene.glove.config.backend == hal::Backend::kSim) {
    s.fail("kind", "the sim glove sends fingertip positions; use 'positions' or another glove.backend");
  }
  const toml::array* bones = s.array("bone_lengths");
  if (bones == nullptr) return;
  if (scene.hand.kind != hal::SampleKind::kAngles) {
    s.fail("bone_lengths", "only used with hand.kind = 'angles'");
  }
  s.check(bones->size() == hal::kFingers, "bone_lengths",
          "expected 5 fingers (thumb .. little) of 3 lengths, got " + std::to_string(bones->size()));
  std::array<std::array<double, 3>, hal::kFingers> lengths{};
  for (std::size_t f = 0; f < hal::kFingers; ++f) {
    const toml::node& finger = *bones->get(f);
    const std::string key = s.key("bone_lengths") + "[" + std::to_string(f) + "]";
    const toml::array* segments = finger.as_array();
    if (segments == nullptr || segments->size() != 3) {
      scene_detail::fail(s.context(), finger.source().begin, key, "expected 3 segment lengths");
    }
    for (std::size_t j = 0; j < 3; ++j) {
      const std::string element = key + "[" + std::to_string(j) + "]";
      lengths[f][j] = as_number(s.context(), *segments->get(j), element);
      if (!(lengths[f][j] > 0.0)) {
        scene_detail::fail(s.context(), segments->get(j)->source().begin, element,
                           "must be > 0, got " + show(lengths[f][j]));
      }
    }
  }
  scene.hand.bone_lengths = lengths;
}

void read_filter(const Section& root, Scene& scene) {
  const Section s = root.table("filter", {"enabled", "min_cutoff", "beta", "d_cutoff"});
  auto& f = scene.filter;
  f.enabled = s.boolean("enabled").value_or(f.enabled);
  f.min_cutoff = s.number_in("min_cutoff", 0.0, true, kMaxCutoffHz, false, "Hz").value_or(f.min_cutoff);
  f.beta = s.non_negative("beta").value_or(f.beta);
  f.d_cutoff = s.number_in("d_cutoff", 0.0, true, kMaxCutoffHz, false, "Hz").value_or(f.d_cutoff);
}

/// Whether the points span more than a line (Umeyama's fit needs it to fix the rotation).
bool spans_a_plane(const std::vector<deform::Vec3>& points) {
  const deform::Vec3& origin = points.front();
  deform::Vec3 far = origin;
  double far_distance = 0.0;
  for (const auto& p : points) {
    const double d = std::sqrt(deform::dot(p - origin, p - origin));
    if (d > far_distance) {
      far_distance = d;
      far = p;
    }
  }
  if (far_distance == 0.0) return false;
  double area = 0.0;
  for (const auto& p : points) {
    const deform::Vec3 c = deform::cross(far - origin, p - origin);
    area = std::max(area, std::sqrt(deform::dot(c, c)));
  }
  return area > 1e-6 * far_distance * far_distance;
}

void read_registration(const Section& root, Scene& scene) {
  const Section s = root.table("registration", {"scale", "rotation", "axis_angle", "translation", "landmarks"});
  auto& r = scene.registration;
  r.scale = s.positive("scale").value_or(r.scale);
  if (s.has("rotation") && s.has("axis_angle")) {
    s.fail("axis_angle", "give either registration.rotation or registration.axis_angle, not both");
  }
  if (const toml::array* q = s.array("rotation")) {
    s.check(q->size() == 4, "rotation",
            "expected a quaternion [w, x, y, z], got " + std::to_string(q->size()) + " elements");
    double norm = 0.0;
    for (std::size_t i = 0; i < 4; ++i) {
      r.rotation[i] = as_number(s.context(), *q->get(i), s.key("rotation") + "[" + std::to_string(i) + "]");
      norm += r.rotation[i] * r.rotation[i];
    }
    norm = std::sqrt(norm);
    // Loose enough for hand-typed 0.7071, tight enough to catch a swapped or missing component.
    s.check(std::abs(norm - 1.0) < 1e-3, "rotation", "not a unit quaternion (norm " + show(norm) + ")");
    for (double& c : r.rotation) c /= norm;
  }
  if (const toml::array* a = s.array("axis_angle")) {
    s.check(a->size() == 4, "axis_angle",
            "expected [ax, ay, az, angle_rad], got " + std::to_string(a->size()) + " elements");
    double v[4];
    for (std::size_t i = 0; i < 4; ++i) {
      v[i] = as_number(s.context(), *a->get(i), s.key("axis_angle") + "[" + std::to_string(i) + "]");
    }
    // hypot, not the square root of the squares: an axis of 1e300 overflowed to inf, and the
    // rotation came out as a quaternion of norm cos(angle / 2), refused later without this key.
    const double axis = std::hypot(v[0], v[1], v[2]);
    s.check(axis > 0.0, "axis_angle", "the axis must not be zero");
    const double half = 0.5 * v[3];
    r.rotation = {std::cos(half), std::sin(half) * v[0] / axis, std::sin(half) * v[1] / axis,
                  std::sin(half) * v[2] / axis};
  }
  r.translation = s.vec3("translation").value_or(r.translation);

  const toml::array* landmarks = s.array("landmarks");
  if (landmarks == nullptr) return;
  for (const auto explicit_key : {"scale", "rotation", "axis_angle", "translation"}) {
    if (s.has(explicit_key)) {
      s.fail(explicit_key, "not used with registration.landmarks (the transform is fitted to them)");
    }
  }
  s.check(landmarks->size() >= 3, "landmarks", "needs at least 3 landmarks, got " + std::to_string(landmarks->size()));
  std::vector<deform::Vec3> glove_points, model_points;
  for (std::size_t i = 0; i < landmarks->size(); ++i) {
    const toml::node& node = *landmarks->get(i);
    const std::string key = s.key("landmarks") + "[" + std::to_string(i) + "]";
    const toml::table* table = node.as_table();
    if (table == nullptr) {
      scene_detail::fail(
          s.context(), node.source().begin, key,
          "expected a table {glove = [x, y, z], model = [x, y, z]}, got " + std::string(type_name(node)));
    }
    const Section l(s.context(), table, key, node.source().begin);
    l.allow({"glove", "model"});
    l.require("glove");
    l.require("model");
    r.landmarks.push_back({*l.vec3("glove"), *l.vec3("model")});
    glove_points.push_back(r.landmarks.back().glove);
    model_points.push_back(r.landmarks.back().model);
  }
  s.check(spans_a_plane(glove_points), "landmarks", "the glove points lie on one line; the rotation is undetermined");
  s.check(spans_a_plane(model_points), "landmarks", "the model points lie on one line; the rotation is undetermined");
}

void read_haptic(const Section& root, Scene& scene) {
  const Section s = root.table(
      "haptic", {"sink", "queue_capacity", "lcm", "serial", "can", "usb", "gain", "max_force", "max_force_rate"});
  auto& haptic = scene.haptic;
  HapticLimits& limits = scene.haptic_limits;
  limits.gain = s.non_negative("gain").value_or(limits.gain);
  limits.max_force = s.positive("max_force").value_or(limits.max_force);
  limits.max_force_rate = s.number_in("max_force_rate", 0.0, true, kMaxForceRate, false, "N/s: 1000 N in a millisecond")
                              .value_or(limits.max_force_rate);
  try {
    limits.validate();
  } catch (const std::invalid_argument& e) {
    s.fail("max_force", e.what());
  }
  const std::string sink = s.string("sink").value_or("none");
  haptic.sink = s.choice<hal::SinkKind>("sink", {{"none", hal::SinkKind::kNone},
                                                 {"lcm", hal::SinkKind::kLcm},
                                                 {"serial", hal::SinkKind::kSerial},
                                                 {"can", hal::SinkKind::kCan},
                                                 {"usb", hal::SinkKind::kUsb}})
                    .value_or(hal::SinkKind::kNone);
  check_backend_sections(s, "sink", sink, {"lcm", "serial", "can", "usb"});
  if (haptic.sink == hal::SinkKind::kNone) {
    if (s.has("queue_capacity")) s.fail("queue_capacity", "only used with a haptic sink (haptic.sink is 'none')");
    return;
  }
  if (scene.model.normals == NormalsSource::kNone) {
    s.fail("sink", "haptic feedback needs the traction, which needs normals (model.normals is 'none')");
  }
  if (const auto q = s.integer_in("queue_capacity", 2, 1 << 20)) haptic.queue_capacity = static_cast<std::size_t>(*q);
  switch (haptic.sink) {
    case hal::SinkKind::kLcm:
      read_lcm_transport(s.table("lcm", {"url", "channel"}), scene.lcm.url, haptic.lcm.url, haptic.lcm.haptic_channel);
      break;
    case hal::SinkKind::kSerial:
      read_serial(s.table("serial", {"device", "baud", "reconnect_ms"}), haptic.serial);
      break;
    case hal::SinkKind::kCan: read_can(s.table("can", {"interface", "fd", "base_id"}), haptic.can); break;
    case hal::SinkKind::kUsb: {
      const Section usb = s.table("usb", {"vendor_id", "product_id", "interface", "out_endpoint", "transfer"});
      read_usb(usb, haptic.usb);
      haptic.max_force = limits.max_force;  // the sink bounds every force again, itself
      const hal::UsbConfig& glove = scene.glove.config.usb;
      // USB lets an interface be claimed once: the source holds the glove's.
      if (scene.glove.config.backend == hal::Backend::kUsb && glove.vendor_id == haptic.usb.vendor_id &&
          glove.product_id == haptic.usb.product_id && glove.interface_number == haptic.usb.interface_number) {
        usb.fail("interface", "the glove source claims interface " + std::to_string(glove.interface_number) +
                                  " of this device; the OUT endpoint must be on an interface of its own");
      }
      break;
    }
    case hal::SinkKind::kNone: break;
  }
}

void read_loop(const Section& root, Scene& scene) {
  const Section s = root.table("loop", {"rate_hz", "realtime", "lock_memory", "cpu"});
  auto& loop = scene.loop;
  loop.rate_hz = s.number_in("rate_hz", 50.0, false, 2000.0, false).value_or(loop.rate_hz);
  if (const toml::node* n = s.node("realtime"); n != nullptr && n->is_boolean()) {
    loop.realtime = *s.boolean("realtime") ? RealtimeMode::kTry : RealtimeMode::kOff;
  } else if (n != nullptr) {
    loop.realtime =
        s.choice<RealtimeMode>("realtime", {{"try", RealtimeMode::kTry}, {"require", RealtimeMode::kRequire}})
            .value_or(loop.realtime);
  }
  loop.lock_memory = s.boolean("lock_memory").value_or(loop.lock_memory);
  // glibc's CPU_SETSIZE is 1024: the pinning takes CPUs 0 to 1023, so a larger one is refused here,
  // by its key, rather than by the loop once the model is loaded.
  if (const auto cpu = s.integer_in("cpu", -1, 1023)) loop.cpu = static_cast<int>(*cpu);
}

void read_lcm(const Section& root, Scene& scene) {
  const Section s = root.table("lcm", {"url", "publish"});
  if (const auto url = s.string("url")) {
    if (const std::string problem = lcm_url_problem(*url); !problem.empty()) s.fail("url", problem);
    scene.lcm.url = *url;
  }
  scene.lcm.publish = s.boolean("publish").value_or(scene.lcm.publish);
}

void read_output(const Section& root, const std::string& base_dir, Scene& scene) {
  const Section s = root.table("output", {"model", "log", "json", "flush_interval_ms", "tick_interval_ms"});
  auto& out = scene.output;
  out.model = path_value(s, "model", base_dir);
  if (out.model) {
    const std::string ext = lower_extension(*out.model);
    s.check(ext == ".ply" || ext == ".xyz", "model", "unsupported output format '" + ext + "'; expected .ply or .xyz");
    s.check(*out.model != scene.model.path, "model",
            "would overwrite the input model (model.path); the base model must survive to replay the log");
  }
  out.log = path_value(s, "log", base_dir);
  out.json = path_value(s, "json", base_dir);
  if (const auto flush = timeout_ms(s, "flush_interval_ms")) {
    if (!out.log) s.fail("flush_interval_ms", "only used with output.log");
    out.flush_interval_ms = *flush;
  }
  if (const auto ticks = timeout_ms(s, "tick_interval_ms", /*zero_allowed=*/true)) {
    if (!out.log) s.fail("tick_interval_ms", "only used with output.log");
    out.tick_interval_ms = *ticks;
  }
}

std::string format_message(const std::string& file, int line, int column, const std::string& key,
                           const std::string& problem) {
  std::string where = file;
  if (line > 0) where += ":" + std::to_string(line) + ":" + std::to_string(column);
  return where + ": " + key + ": " + problem;
}

}  // namespace

SceneError::SceneError(std::string file, int line, int column, std::string key, std::string problem)
    : std::runtime_error(format_message(file, line, column, key, problem)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      key_(std::move(key)),
      problem_(std::move(problem)) {}

Scene parse_scene(std::string_view text, const std::string& path_for_errors, const std::string& base_dir) {
  const Context context{path_for_errors};
  toml::table document;
  try {
    document = toml::parse(text, path_for_errors);
  } catch (const toml::parse_error& error) {
    const auto at = error.source().begin;
    throw SceneError(path_for_errors, static_cast<int>(at.line), static_cast<int>(at.column), "toml",
                     std::string(error.description()));
  }

  Scene scene;
  scene.file = path_for_errors;
  scene.text = std::string(text);
  scene.base_dir = base_dir;
  const Section root(context, &document, "", toml::source_position{1, 1});
  root.allow({"model", "material", "kernel", "deform", "heuristic", "glove", "hand", "filter", "registration", "haptic",
              "loop", "lcm", "output"});
  // Order matters only where one section's meaning depends on another's: the model's normals
  // (deform, haptic), the region (deform), the LCM URL (glove and haptic defaults).
  read_model(root, base_dir, scene);
  read_material_and_kernel(root, scene);
  read_heuristic(root, scene);
  read_deform(root, scene);
  read_lcm(root, scene);
  read_glove(root, scene);
  read_hand(root, scene);
  read_filter(root, scene);
  read_registration(root, scene);
  read_haptic(root, scene);
  read_loop(root, scene);
  read_output(root, base_dir, scene);
  return scene;
}

Scene load_scene(const std::string& path) {
  // Only a regular file is a scene: /dev/zero never ends (its read grew without bound), a FIFO
  // waits for a writer, and a directory read as empty, reported as a missing key.
  std::string text;
  try {
    text = base::read_regular_file(path);
  } catch (const base::FileReadError& e) {
    throw SceneError(path, 0, 0, "file", e.what());
  }
  std::error_code error;
  std::filesystem::path dir = std::filesystem::absolute(std::filesystem::path(path), error).parent_path();
  if (error) dir = std::filesystem::path(path).parent_path();
  return parse_scene(text, path, dir.lexically_normal().string());
}

}  // namespace sculpt::rt
