#!/usr/bin/python3
"""Plot a recorded session over time: the force each finger felt and the loop's tick times.

    scripts/plot_session.py LOG --out PNG [--types DIR]

Top: the haptic force magnitude per finger (newtons, SCULPT_HAPTIC) when the session sent
haptics over LCM, otherwise |F| = |P_f - A| of each collision (model units, SCULPT_COLLISION).
Bottom: each logged tick's compute time and its budget (microseconds, SCULPT_TICK; the log keeps
every tick in which something happened, every slow one, and a quiet one per
output.tick_interval_ms). Time is seconds since the session's first event. Reads the log with scripts/lcm_log.py; plots with Debian's
python3-matplotlib.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import lcm_log  # noqa: E402

FINGERS = ["thumb", "index", "middle", "ring", "little"]


def main():
    parser = argparse.ArgumentParser(description="Plot a session's forces and tick times to a PNG")
    parser.add_argument("log")
    parser.add_argument("--out", required=True, help="the picture, .png")
    parser.add_argument("--types", default=lcm_log.default_types_dir())
    args = parser.parse_args()
    if not args.out.lower().endswith(".png"):
        sys.exit(f"plot_session.py: error: --out {args.out}: the picture is written as PNG; name it .png")
    try:
        import matplotlib
        matplotlib.use("Agg")  # no display needed
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("plot_session.py: error: needs python3-matplotlib (scripts/setup.sh installs it)")

    types = lcm_log.load_types(args.types)
    start = None
    haptic = {}     # (hand, finger) -> ([t], [N])
    collision = {}  # (hand, finger) -> ([t], [|F|])
    ticks_t, ticks_us, budget_us = [], [], []
    haptic_commands = 0
    damage = None
    try:
        for _, utime, channel, m in lcm_log.decoded(args.log, types):
            if start is None:
                start = utime
            t = (utime - start) * 1e-6
            if channel == "SCULPT_HAPTIC":
                haptic_commands += 1
                for f, v in enumerate(m.force):
                    series = haptic.setdefault((m.hand, f), ([], []))
                    series[0].append(t)
                    series[1].append(math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2))
            elif channel == "SCULPT_COLLISION":
                series = collision.setdefault((m.hand, m.finger), ([], []))
                series[0].append(t)
                series[1].append(math.sqrt(sum(c * c for c in m.force)))
            elif channel == "SCULPT_TICK":
                ticks_t.append(t)
                ticks_us.append(m.tick_time_us)
                budget_us.append(m.budget_us)
    except lcm_log.LogDamage as e:
        damage = e  # plot what came before it, and say so
    except (OSError, ValueError) as e:
        sys.exit(f"plot_session.py: error: {e}")
    if start is None:
        sys.exit(f"plot_session.py: error: {args.log}: no events")

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    if any(max(v) > 0 for _, v in haptic.values()):
        for (hand, f), (t, v) in sorted(haptic.items()):
            if max(v) > 0:
                top.plot(t, v, label=f"hand {hand} {FINGERS[f]}")
        top.set_ylabel("haptic force (N)")
    else:
        for (hand, f), (t, v) in sorted(collision.items()):
            top.plot(t, v, "o", markersize=3, label=f"hand {hand} {FINGERS[f % 5]}")
        top.set_ylabel("|F| per collision (model units)")
    if top.lines:
        top.legend(loc="upper right", fontsize="small")
    top.set_title(os.path.basename(args.log) + (f"  (cut at byte {damage.offset})" if damage else ""))
    bottom.plot(ticks_t, ticks_us, linewidth=0.6, label="tick compute time")
    if budget_us:
        bottom.plot(ticks_t, budget_us, linewidth=0.6, label="time left in the period")
    bottom.set_yscale("log")
    bottom.set_ylabel("microseconds")
    bottom.set_xlabel("seconds since the session's first event")
    bottom.legend(loc="upper right", fontsize="small")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}: {haptic_commands} haptic commands, "
          f"{sum(len(t) for t, _ in collision.values())} collisions, {len(ticks_t)} ticks")


if __name__ == "__main__":
    main()
