#!/usr/bin/python3
"""Read a glovesculpt durable log (LCM's log-file format) without an LCM Python module.

Debian 12 packages no Python LCM module, so the file format is parsed here, as LCM documents
it: each event is a big-endian sync word 0xEDA1DA01, an int64 event number, an int64
timestamp (microseconds since the Unix epoch), an int32 channel length, an int32 data length,
the channel name and the data. The data are decoded with the classes lcm-gen generates from
lcmtypes/lcm/*.lcm at build time (build/lcmtypes/python/sculpt_lcm).

    scripts/lcm_log.py LOG [--types DIR]     one JSON object: counts per channel and what the
                                             station's run summary also reports; a log cut by
                                             a crash is read up to the cut ("damage" names its
                                             offset); what the log's checks say ("checks": the
                                             events whose bytes changed); a file that is not a
                                             log is exit 1
As a module: events(path) yields raw events, decoded(path) decoded ones, resign(blob) makes a
log's checks (SCULPT_CHECK, logging/event_check.hpp) match its bytes again.
"""
import argparse
import json
import os
import struct
import sys
import zlib

SYNC = 0xEDA1DA01
HEADER = struct.Struct(">IqqII")  # sync, event number, utime, channel length, data length
MAX_CHANNEL = 256  # LCM allows 63 characters; anything longer is damage, not a channel

CHANNEL_TYPES = {
    "SCULPT_SESSION": "session_header_t",
    "SCULPT_GLOVE": "glove_sample_t",
    "SCULPT_FINGERTIP": "fingertip_state_t",
    "SCULPT_COLLISION": "collision_event_t",
    "SCULPT_TICK": "tick_stats_t",
    "SCULPT_HAPTIC": "haptic_command_t",
    "SCULPT_CHECK": "log_check_t",
}
CHECK_CHANNEL = b"SCULPT_CHECK"


class LogDamage(Exception):
    """The file stops being a log at `offset` (a cut event, or bytes that are not one)."""

    def __init__(self, path, offset, what):
        super().__init__(f"{path}: byte offset {offset}: {what}")
        self.offset = offset


def resign(blob):
    """Recomputes in place (a bytearray) every SCULPT_CHECK's CRC-32s over the events' bytes as
    they are now. For tests that edit a field to reach the guards behind the checks: the log a
    station would write with those values, rather than a log changed after it was written (which
    the checks find). The log must be whole; a check's payload is its type's fingerprint, int64
    first_event, int32 count, then count int32 CRCs."""
    spans, checks, at = {}, [], 0
    while at < len(blob):
        _, number, _, channel_length, data_length = HEADER.unpack_from(blob, at)
        end = at + HEADER.size + channel_length + data_length
        if bytes(blob[at + HEADER.size:at + HEADER.size + channel_length]) == CHECK_CHANNEL:
            checks.append(at + HEADER.size + channel_length)
        else:
            spans[number] = (at, end)
        at = end
    for data in checks:
        first, count = struct.unpack_from(">qi", blob, data + 8)
        for k in range(count):
            start, end = spans[first + k]
            struct.pack_into(">I", blob, data + 20 + 4 * k, zlib.crc32(blob[start:end]))


def events(path):
    """(offset, number, utime, channel, data) for every event; raises LogDamage where the
    file stops being a log. A log cut at its end (what a crash leaves) raises it too, after
    every complete event."""
    with open(path, "rb") as f:
        blob = f.read()
    at = 0
    while at < len(blob):
        if len(blob) - at < HEADER.size:
            raise LogDamage(path, at, "cut inside an event header")
        sync, number, utime, channel_length, data_length = HEADER.unpack_from(blob, at)
        if sync != SYNC:
            raise LogDamage(path, at, f"no sync word (0x{sync:08X}): not an LCM log, or damaged")
        if channel_length == 0 or channel_length > MAX_CHANNEL:
            raise LogDamage(path, at, f"channel length {channel_length} is not a channel's")
        end = at + HEADER.size + channel_length + data_length
        if end > len(blob):
            raise LogDamage(path, at, "cut inside an event")
        channel = blob[at + HEADER.size:at + HEADER.size + channel_length].decode("utf-8", "replace")
        yield at, number, utime, channel, blob[at + HEADER.size + channel_length:end]
        at = end


def check_events(path):
    """What the log's checks (SCULPT_CHECK) say of its events: how many a check covered, those
    that do not match theirs (offset, event number), and how many no check covered (a crash's
    tail, a log without checks). Reads up to any damage."""
    crcs, checked, failed = {}, 0, []
    try:
        for offset, number, utime, channel, data in events(path):
            if channel != "SCULPT_CHECK":
                name = channel.encode("utf-8")
                head = HEADER.pack(SYNC, number, utime, len(name), len(data))
                crcs[number] = (offset, zlib.crc32(head + name + data))
                continue
            first, count = struct.unpack_from(">qi", data, 8)  # past the type's fingerprint
            for k in range(count):
                seen = crcs.pop(first + k, None)
                if seen is None:
                    continue
                checked += 1
                if seen[1] != struct.unpack_from(">I", data, 20 + 4 * k)[0]:
                    failed.append({"offset": seen[0], "event": first + k})
    except (LogDamage, struct.error):
        pass
    return {"checked": checked, "failed": failed, "unchecked": len(crcs)}


def load_types(types_dir):
    sys.path.insert(0, types_dir)
    import sculpt_lcm  # noqa: E402  (generated at build time)
    return {channel: getattr(sculpt_lcm, name) for channel, name in CHANNEL_TYPES.items()}


def decoded(path, types):
    """(offset, utime, channel, message or None) for every event; None for a channel of no
    known type. A message that does not decode raises ValueError naming the offset."""
    for offset, _, utime, channel, data in events(path):
        kind = types.get(channel)
        if kind is None:
            yield offset, utime, channel, None
            continue
        try:
            yield offset, utime, channel, kind.decode(data)
        except Exception as e:  # lcm-gen's decode raises ValueError on a wrong fingerprint
            raise ValueError(f"{path}: byte offset {offset}: {channel} does not decode: {e}") from e


def summary(path, types):
    counts = {}
    tick_times = []
    collisions_per_finger = {}  # (hand, finger) -> collisions
    peak_haptic = 0.0
    damage = None
    try:
        for _, _, channel, m in decoded(path, types):
            counts[channel] = counts.get(channel, 0) + 1
            if channel == "SCULPT_TICK":
                tick_times.append(m.tick_time_us)
            elif channel == "SCULPT_COLLISION":
                key = (m.hand, m.finger)
                collisions_per_finger[key] = collisions_per_finger.get(key, 0) + 1
            elif channel == "SCULPT_HAPTIC":
                for f in m.force:
                    peak_haptic = max(peak_haptic, (f[0] ** 2 + f[1] ** 2 + f[2] ** 2) ** 0.5)
    except LogDamage as e:
        damage = {"offset": e.offset, "what": str(e)}
    return {
        "log": path,
        "channels": counts,
        "ticks": counts.get("SCULPT_TICK", 0),
        "collisions": counts.get("SCULPT_COLLISION", 0),
        "glove_samples": counts.get("SCULPT_GLOVE", 0),
        "fingertips": counts.get("SCULPT_FINGERTIP", 0),
        "haptic": counts.get("SCULPT_HAPTIC", 0),
        # As the run summary lists them: one entry per finger that collided.
        "collisions_per_finger": [{"hand": h, "finger": f, "collisions": n}
                                  for (h, f), n in sorted(collisions_per_finger.items())],
        "tick_time_max_us": max(tick_times) if tick_times else None,
        "peak_haptic_force": peak_haptic,
        "damage": damage,
        "checks": check_events(path),
    }


def default_types_dir():
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.join(here, "..", "build", "lcmtypes", "python")


def main():
    parser = argparse.ArgumentParser(description="Summarise a glovesculpt durable log (LCM log format)")
    parser.add_argument("log")
    parser.add_argument("--types", default=default_types_dir(),
                        help="folder holding the generated sculpt_lcm package (default: build/lcmtypes/python)")
    args = parser.parse_args()
    if not os.path.isdir(os.path.join(args.types, "sculpt_lcm")):
        sys.exit(f"lcm_log.py: error: no generated sculpt_lcm package in {args.types} (build the project first)")
    try:
        result = summary(args.log, load_types(args.types))
    except OSError as e:
        sys.exit(f"lcm_log.py: error: {args.log}: {e.strerror}")
    except ValueError as e:
        sys.exit(f"lcm_log.py: error: {e}")
    if result["damage"] and result["damage"]["offset"] == 0:
        sys.exit(f"lcm_log.py: error: {args.log}: not an LCM log (no event at byte 0)")
    # A log cut later (what a crash leaves) is summarised up to the cut, which "damage" names.
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
