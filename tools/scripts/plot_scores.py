#!/usr/bin/env python3
"""Plot per-frame detection outcomes and scores written by evaluate_sequences.

usage: plot_scores.py PER_FRAME_CSV OUT_DIR

Writes OUT_DIR/scores_<sequence>.png (one strip per mode: TP green, partial orange, FP red,
miss grey, frames that need no lane hatched; below, the left/right peak response of each depth
mode and the plane angle error) and OUT_DIR/summary.png (per sequence and mode, % of all frames:
TP, partial and miss of the frames that require a lane, FP anywhere, and the frames that need no
lane without a wrong report).
"""
import csv
import os
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

COLOURS = {"TP": "#2ca02c", "partial": "#ff9f1c", "FP": "#d62728", "miss": "#b0b0b0"}
NO_LANE = "#dcdcf0"  # frames that need no lane (no boundary, or an intersection ahead)


def required(row):
    """True when the frame requires a lane (older CSVs without the column: every frame)."""
    return row.get("lane_required", "1") not in ("0", "false")


def percentages(rows):
    """(TP, partial, FP, miss) of the lane frames and FP of all frames, in %."""
    req = [r for r in rows if required(r)]
    n = max(len(req), 1)
    share = {o: 100.0 * sum(r["outcome"] == o for r in req) / n for o in ("TP", "partial", "miss")}
    share["FP"] = 100.0 * sum(r["outcome"] == "FP" for r in rows) / max(len(rows), 1)
    return share


def read_rows(path):
    data = OrderedDict()  # sequence -> mode -> list of rows
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            data.setdefault(row["sequence"], OrderedDict()).setdefault(row["mode"], []).append(row)
    return data


def number(text):
    try:
        return float(text)
    except ValueError:
        return float("nan")


def plot_sequence(name, modes, out_path):
    fig, (ax_strip, ax_score, ax_angle) = plt.subplots(
        3, 1, figsize=(10, 2.2 + 0.45 * len(modes) + 3.2), sharex=True,
        gridspec_kw={"height_ratios": [0.45 * len(modes) + 0.3, 1.6, 1.2]})
    labels = list(modes.keys())
    for i, mode in enumerate(labels):
        rows = modes[mode]
        for outcome, colour in COLOURS.items():
            frames = [int(r["frame"]) for r in rows if r["outcome"] == outcome]
            ax_strip.broken_barh([(f - 0.5, 1.0) for f in frames], (i - 0.4, 0.8), color=colour)
        optional = [int(r["frame"]) for r in rows if not required(r)]
        ax_strip.broken_barh([(f - 0.5, 1.0) for f in optional], (i - 0.4, 0.8),
                             facecolor="none", edgecolor="#404080", hatch="///", lw=0)
        share = percentages(rows)
        labels[i] = "%s  TP %.0f%% FP %.0f%%" % (mode, share["TP"], share["FP"])
    ax_strip.set_yticks(range(len(labels)))
    ax_strip.set_yticklabels(labels, fontsize=8)
    ax_strip.set_ylim(-0.6, len(labels) - 0.4)
    ax_strip.invert_yaxis()
    ax_strip.set_title("%s: per-frame outcome (scoring.h)" % name)
    ax_strip.legend(handles=[Patch(color=c, label=o) for o, c in COLOURS.items()] +
                    [Patch(facecolor="none", edgecolor="#404080", hatch="///",
                           label="no lane needed")],
                    loc="upper right", fontsize=7, ncol=5)
    for mode, style in (("paper", "--"), ("improved", "-")):
        if mode not in modes:
            continue
        rows = modes[mode]
        frames = [int(r["frame"]) for r in rows]
        ax_score.plot(frames, [number(r["left_score"]) for r in rows], style, color="#2ca02c",
                      lw=0.9, label="%s left peak R" % mode)
        ax_score.plot(frames, [number(r["right_score"]) for r in rows], style, color="#ff7f0e",
                      lw=0.9, label="%s right peak R" % mode)
        ax_angle.plot(frames, [number(r["angle_error_deg"]) for r in rows], style, marker=".",
                      ms=2, lw=0.6, label="%s plane angle error" % mode)
    ax_score.set_ylabel("peak response")
    ax_score.legend(fontsize=7, ncol=2, loc="lower right")
    ax_angle.axhline(3.0, color="k", lw=0.6, ls=":")
    ax_angle.set_yscale("symlog", linthresh=0.1)
    ax_angle.set_ylabel("angle err (deg)")
    ax_angle.set_xlabel("frame")
    ax_angle.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    fig.savefig(out_path, dpi=90)
    plt.close(fig)


def plot_summary(data, out_path):
    sequences = list(data.keys())
    modes = []
    for s in sequences:
        for m in data[s]:
            if m not in modes:
                modes.append(m)
    fig, ax = plt.subplots(figsize=(max(8.0, 1.05 * len(sequences) + 1.5), 4.6))
    width = 0.8 / max(len(modes), 1)
    for j, mode in enumerate(modes):
        for i, s in enumerate(sequences):
            rows = data[s].get(mode, [])
            n = max(len(rows), 1)
            x = i + (j - (len(modes) - 1) / 2.0) * width
            bottom = 0.0
            # % of all frames: lane frames by outcome, FP anywhere, then the no-lane frames
            # without a wrong report
            for outcome in ("TP", "partial", "FP", "miss", "no lane"):
                if outcome == "FP":
                    count = sum(r["outcome"] == "FP" for r in rows)
                elif outcome == "no lane":
                    count = sum(not required(r) and r["outcome"] != "FP" for r in rows)
                else:
                    count = sum(required(r) and r["outcome"] == outcome for r in rows)
                v = 100.0 * count / n
                ax.bar(x, v, width * 0.95, bottom=bottom,
                       color=COLOURS.get(outcome, NO_LANE), edgecolor="white", lw=0.3)
                bottom += v
            ax.text(x, 101, mode.replace("-colour", "-c").replace("improved", "imp"),
                    rotation=90, fontsize=7, ha="center", va="bottom")
    ax.set_xticks(range(len(sequences)))
    ax.set_xticklabels(sequences, rotation=30, ha="right", fontsize=8)
    ax.set_ylim(0, 125)
    ax.set_ylabel("% of frames")
    ax.legend(handles=[Patch(color=c, label=o) for o, c in COLOURS.items()] +
              [Patch(color=NO_LANE, label="no lane needed, nothing wrong")], fontsize=8,
              loc="upper right", ncol=5)
    ax.set_title("TP / partial / FP / miss per sequence and mode (% of all frames)")
    fig.tight_layout()
    fig.savefig(out_path, dpi=90)
    plt.close(fig)


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    csv_path, out_dir = argv[1], argv[2]
    if not os.path.isfile(csv_path):
        sys.stderr.write("plot_scores.py: %s not found\n" % csv_path)
        return 1
    os.makedirs(out_dir, exist_ok=True)
    data = read_rows(csv_path)
    if not data:
        sys.stderr.write("plot_scores.py: %s holds no rows\n" % csv_path)
        return 1
    for name, modes in data.items():
        plot_sequence(name, modes, os.path.join(out_dir, "scores_%s.png" % name))
    plot_summary(data, os.path.join(out_dir, "summary.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
