#!/usr/bin/env python3
"""Fit the lane model's confidence calibration: isotonic regression of "correct" on the evidence.

usage: fit_confidence.py LANE_MODEL_CSV [--mode improved] [--min-block 50]

LANE_MODEL_CSV is evaluate_sequences' per-boundary file (build/eval/lane_model.csv: columns
reported, evidence, correct). Every published boundary of the given mode is a sample (evidence,
correct). The pool-adjacent-violators algorithm makes the fraction correct non-decreasing in the
evidence; blocks of fewer than --min-block samples are pooled with a neighbour (so that a knot
rests on enough boundaries). Each block becomes a knot at its mean evidence with
P = (correct + 1) / (boundaries + 2) (never 0 or 1 from a finite sample), plus the ends
(0, first P) and (1, last P). The knots are printed as the C++ table of
calibratedConfidence() in src/core/lane_model.cpp, followed by the blocks.
"""
import argparse
import csv
import sys


def pav(samples, min_block):
    """Blocks [sum_evidence, correct, count] of samples sorted by evidence, non-decreasing in
    correct / count, each of at least min_block samples (but the last if all are fewer)."""
    blocks = []
    for evidence, correct in sorted(samples):
        blocks.append([evidence, correct, 1])
        # merge while the last block violates monotonicity or the previous one is too small
        while len(blocks) > 1 and (
                blocks[-2][1] * blocks[-1][2] >= blocks[-1][1] * blocks[-2][2]
                or blocks[-2][2] < min_block):
            e, c, n = blocks.pop()
            blocks[-1][0] += e
            blocks[-1][1] += c
            blocks[-1][2] += n
    while len(blocks) > 1 and blocks[-1][2] < min_block:  # a small last block joins its neighbour
        e, c, n = blocks.pop()
        blocks[-1][0] += e
        blocks[-1][1] += c
        blocks[-1][2] += n
    return blocks


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("csv")
    parser.add_argument("--mode", default="improved")
    parser.add_argument("--min-block", type=int, default=50)
    args = parser.parse_args(argv[1:])
    samples = []
    with open(args.csv) as f:
        for row in csv.DictReader(f):
            if row["mode"] != args.mode or row["reported"] != "1":
                continue
            samples.append((float(row["evidence"]), int(row["correct"])))
    if not samples:
        sys.stderr.write("fit_confidence: no published boundaries of mode %s\n" % args.mode)
        return 1
    blocks = pav(samples, args.min_block)
    knots = [(b[0] / b[2], (b[1] + 1.0) / (b[2] + 2.0)) for b in blocks]
    knots = [(0.0, knots[0][1])] + knots + [(1.0, knots[-1][1])]
    print("// %d boundaries, %d correct; %d blocks (min %d)" %
          (len(samples), sum(c for _, c in samples), len(blocks), args.min_block))
    print("static constexpr float kKnots[][2] = {%s};" %
          ", ".join("{%.4ff, %.4ff}" % k for k in knots))
    for b in blocks:
        print("//   evidence %.3f: %d of %d correct" % (b[0] / b[2], b[1], b[2]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
