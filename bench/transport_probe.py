#!/usr/bin/env python3
"""Collects one run of bench/measure_transport.sh (issue 23): the lane detector's own frame
accounting from /diagnostics (its "<node>: processing" status: cumulative counters, and the
per-window mean/max callback and detect() times) and, for the frame player's runs, the player's
latched summary (diagnostic_msgs/DiagnosticStatus, FramePlayerNodelet). Writes them as JSON.

Ends when the run is over and the nodelet's counters have settled (two consecutive reports with
the same received/processed counts and nothing waiting), or at --timeout:
  --mode player: the run is over when the player's summary arrives;
  --mode bag:    when the file --done-file exists (the script creates it after rosbag play).
"""
import argparse
import json
import os
import sys
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus


def values(status):
    return {kv.key: kv.value for kv in status.values}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True)
    ap.add_argument("--mode", choices=["player", "bag"], required=True)
    ap.add_argument("--node", default="lane_detector", help="substring of the nodelet's name")
    ap.add_argument("--summary-topic", default="/camera/frame_player/summary")
    ap.add_argument("--done-file", default="")
    ap.add_argument("--timeout", type=float, default=300.0)
    ap.add_argument("--subscribe", default="",
                    help="also subscribe to this output (any type) and count its messages "
                         "(bag runs: the nodelet computes nothing without a subscriber)")
    args = ap.parse_args(rospy.myargv()[1:])
    rospy.init_node("transport_probe", anonymous=True, disable_signals=True)

    state = {"reports": [], "summary": None, "windows": [], "outputs": 0,
             "max_queue_wait_ms": None}

    def on_diag(msg):
        for st in msg.status:
            if args.node in st.name and st.name.endswith("processing"):
                v = values(st)
                state["reports"].append(v)
                try:  # over every window, those without a processed frame too (prepare())
                    wait = float(v.get("Max camera_info queue wait (ms)"))
                    if state["max_queue_wait_ms"] is None or wait > state["max_queue_wait_ms"]:
                        state["max_queue_wait_ms"] = wait
                except (TypeError, ValueError):
                    pass
                try:
                    if float(v.get("Mean detector time (ms)", "0")) > 0:
                        state["windows"].append({
                            "callback_ms": float(v.get("Mean processing time (ms)", "nan")),
                            "detect_ms": float(v.get("Mean detector time (ms)", "nan")),
                            "max_ms": float(v.get("Max processing time (ms)", "nan")),
                            "max_cpu_ms": float(v.get("Max processing CPU time (ms)", "nan")),
                        })
                except ValueError:
                    pass

    def on_summary(msg):
        state["summary"] = values(msg)

    rospy.Subscriber("/diagnostics", DiagnosticArray, on_diag, queue_size=50)
    if args.subscribe:
        def on_output(_msg):
            state["outputs"] += 1
        rospy.Subscriber(args.subscribe, rospy.AnyMsg, on_output, queue_size=100)
    if args.mode == "player":
        rospy.Subscriber(args.summary_topic, DiagnosticStatus, on_summary, queue_size=1)

    deadline = time.monotonic() + args.timeout
    over_at = None
    settled = False
    while time.monotonic() < deadline and not rospy.is_shutdown():
        time.sleep(0.1)
        over = (state["summary"] is not None if args.mode == "player"
                else bool(args.done_file) and os.path.exists(args.done_file))
        if not over:
            continue
        if over_at is None:
            over_at = len(state["reports"])
        after = state["reports"][over_at:]
        if len(after) >= 2:
            a, b = after[-2], after[-1]
            keys = ("Frames received", "Frames processed", "Frames synchronised")
            if all(a.get(k) == b.get(k) for k in keys) and b.get("Frames waiting", "0") in ("0", "1"):
                settled = True
                break
    result = {
        "settled": settled,
        "accounting": state["reports"][-1] if state["reports"] else {},
        "windows": state["windows"],
        "max_queue_wait_ms": state["max_queue_wait_ms"],
        "summary": state["summary"],
        "outputs": state["outputs"] if args.subscribe else None,
    }
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    rospy.signal_shutdown("done")
    return 0 if state["reports"] else 1


if __name__ == "__main__":
    sys.exit(main())
