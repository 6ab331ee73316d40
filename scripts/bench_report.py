#!/usr/bin/env python3
"""Write docs/PERFORMANCE.md (and a PNG of time per stage) from bench_core's JSON output.

Called by scripts/bench.sh; every figure in the document comes from the JSON of one run.
"""
import argparse
import os
import json
import re
import sys

SIZES = [(640, 380), (1280, 760)]
# improved detect() against the OpenCV pipeline at commit 085bc57, before the real-streets work
IMPROVED_RATIO_BEFORE = {640: 9.1, 1280: 9.0}
# (label, ours, OpenCV pipeline, note)
STAGES = [
    ("half-binary", "BM_Stage_HalfBinary", "BM_OpenCV_Preprocess", "cvtColor + threshold"),
    ("3D points", "BM_Stage_Points", "BM_OpenCV_Points", "rgbd::depthTo3d"),
    ("normals (ours: + G)", "BM_Stage_Normals", "BM_OpenCV_Normals", "RgbdNormals FALS, CV_32F"),
    ("matching, 2 templates", "BM_Stage_Matching", "BM_OpenCV_Matching", "matchTemplate x2"),
    ("G and R (ours: R)", "BM_Stage_Response", "BM_OpenCV_Response", "per-pixel loops"),
]
# detect()'s own stage timings (StageTimings), in pipeline order
COUNTERS = [
    ("preprocess_ms", "half-binary"),
    ("points_ms", "3D points"),
    ("normals_ms", "normals + G"),
    ("matching_ms", "matching"),
    ("response_ms", "R"),
    ("pca_ms", "seeds + PCA"),
    ("tracing_ms", "tracing"),
    ("plane_ms", "plane"),
]


def medians(path):
    """(context, [(run name, time factor to ms, benchmark)]) of a bench_core JSON: the medians of
    repeated runs, or the single runs."""
    with open(path) as f:
        data = json.load(f)
    out = []
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        unit = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
        out.append((b.get("run_name", b["name"]), unit, b))
    return data["context"], out


def load(path):
    context, runs_in = medians(path)
    runs = {}
    for name, unit, b in runs_in:
        m = re.match(r"(BM_[\w/]+?)/(\d+)", name)
        if not m:
            continue
        runs[(m.group(1), int(m.group(2)))] = {
            "cpu": b["cpu_time"] * unit,
            "real": b["real_time"] * unit,
            "counters": {k: v for k, v in b.items() if k.endswith("_ms")},
            "label": b.get("label", ""),
        }
    return context, runs


def ms(v):
    return "-" if v is None else (f"{v:.3f}" if v < 1 else f"{v:.2f}")


def ratio(a, b):
    return "-" if not a or not b else f"{b / a:.1f}x"


def get(runs, name, w, key="cpu"):
    r = runs.get((name, w))
    return None if r is None else r[key]


def counters(runs, w):
    r = runs.get(("BM_Detect", w))
    if r is None:
        return {}
    # counters are per frame (kAvgIterations), in ms
    return r["counters"]


def plot(runs, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = ["#4c72b0", "#55a868", "#c44e52", "#8172b2", "#ccb974", "#64b5cd"]
    labels = ["half-binary", "points", "normals (+G)", "matching", "G/R", "seeds, PCA, tracing, plane"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.4))
    for ax, (w, h) in zip(axes, SIZES):
        # stage shares, scaled to the whole frame's CPU time (detect()'s stage clocks are wall
        # time; the OpenCV stages were timed one by one)
        c = counters(runs, w)
        ours = [c.get(k, 0.0) for k, _ in COUNTERS[:5]]
        ours.append(sum(c.get(k, 0.0) for k, _ in COUNTERS[5:]))
        cv = [get(runs, s[2], w) or 0.0 for s in STAGES] + [0.0]
        for row, values, total in ((1, ours, get(runs, "BM_Detect", w)),
                                   (0, cv, get(runs, "BM_OpenCV_Pipeline", w))):
            scale = (total or 0.0) / (sum(values) or 1.0)
            left = 0.0
            for i, v in enumerate(values):
                ax.barh(row, v * scale, left=left, color=colours[i],
                        label=labels[i] if row == 0 and w == SIZES[0][0] else None)
                left += v * scale
            ax.text(left, row, f"  {left:.2f} ms", va="center", fontsize=8)
        ax.set_yticks([0, 1], ["OpenCV pipeline", "detect()"])
        ax.set_xlabel("ms per frame (CPU, median), single thread")
        ax.set_title(f"{w}x{h}")
        ax.set_xlim(0, (get(runs, "BM_OpenCV_Pipeline", w) or 1.0) * 1.3)
    fig.legend(loc="lower center", ncol=6, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    fig.savefig(path, dpi=110)


def lane_grid_section(json_path):
    """'## Lane grid' lines from the BM_LaneGrid medians of a bench_core JSON ([] without them)."""
    with open(json_path) as f:
        data = json.load(f)
    rows = []
    for b in data["benchmarks"]:
        name = b.get("run_name", b["name"])
        if not name.startswith("BM_LaneGrid/"):
            continue
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        unit = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}[b.get("time_unit", "ns")]
        rows.append((name.split("/")[1], b.get("label", ""), b["cpu_time"] * unit,
                     b["real_time"] * unit))
    if not rows:
        return []
    what = {"Default": "default (0.1 m, 40 m x 20 m)", "LaneChange": "default, allow_lane_change",
            "Fine5cm": "0.05 m, 40 m x 20 m"}
    L = ["## Lane grid (lane_grid)", "",
         "`LaneGrid::build()` (issue 25: the lane model rasterised into the `lane_grid` occupancy "
         "grid), from the improved mode's lane model after the 640x380 frames, one thread, the "
         "grid's cells reused (`BM_LaneGrid`). Target: < 0.3 ms at the default size.", "",
         "| grid | cells | CPU us | wall us | target < 300 us |", "| --- | --- | ---: | ---: | --- |"]
    for key, label, cpu, real in rows:
        ok = ("met" if cpu < 300 else "NOT met") if key != "Fine5cm" else "-"
        L.append(f"| {what.get(key, key)} | {label} | {cpu:.1f} | {real:.1f} | {ok} |")
    L.append("")
    L.append("The nodelet builds it only while `lane_grid` (or `debug_image`, for its inset) has a "
             "subscriber, and copies the cells into the message (80 kB at the default size).")
    L.append("")
    return L


REAL_STAGES = [("preprocess_ms", "resample + half-binary"), ("points_ms", "points"),
               ("normals_ms", "normals + G"), ("matching_ms", "matching"), ("response_ms", "R"),
               ("road_ms", "road surface"), ("pca_ms", "seeds + PCA"),
               ("tracing_ms", "tracing"), ("classify_ms", "classification"),
               ("plane_ms", "plane + boundaries"), ("model_ms", "lane model")]


def load_real(path):
    """BM_Real_<kind>/<frame> medians of a bench_core JSON: {(kind, frame): run}."""
    runs = {}
    for name, unit, b in medians(path)[1]:
        m = re.match(r"BM_Real_(\w+)/(\w+)", name)
        if not m:
            continue
        runs[(m.group(1), m.group(2))] = {
            "cpu": b["cpu_time"] * unit, "label": b.get("label", ""),
            "pixels": b.get("pixels", 0.0), "scale": b.get("scale", 1.0),
            "counters": {k: v for k, v in b.items() if k.endswith("_ms")}}
    return runs


def real_frames_section(json_path, bench_ns_per_px):
    """'## Real frames' lines (issue 23's targets) from BM_Real_* ([] without them)."""
    real = load_real(json_path)
    frames = []
    for (kind, frame) in real:
        if kind == "Detect" and frame not in frames:
            frames.append(frame)
    if not frames:
        return ["## Real frames", "", "Not measured: ../shared/realdata was absent "
                "(bench_core skips the real frames without it).", ""]
    L = ["## Real frames", "",
         "detect() in the default mode on one real frame per camera of the corpus "
         "(../shared/realdata, LiDAR depth, read in place; bench/bench_real_frames.cpp), at "
         "its native size, again and again after 5 warm-up frames (the steady state of a "
         "drive), one thread, CPU time; `auto scale` is the processing scale the default "
         "`processing_scale: 0` chose (processingScale()), `full scale` the same with "
         "`processing_scale: 1`; the OpenCV pipeline (the paper's stages only) on the same "
         "frame at its native size in the same run. ns/px per native pixel; the generated "
         f"640x380 frame's improved mode is {bench_ns_per_px:.1f} ns/px in this run." if
         bench_ns_per_px else "", "",
         "| frame | size | auto scale | default ms | ns/px | x bench ns/px | full scale ms | "
         "OpenCV pipeline ms | OpenCV / default | target |",
         "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |"]
    for f in frames:
        d = real[("Detect", f)]
        full = real.get(("DetectFullScale", f))
        cv = real.get(("OpenCV", f))
        nspx = d["cpu"] * 1e6 / d["pixels"] if d["pixels"] else None
        w, h = (int(x) for x in d["label"].split("x")) if "x" in d["label"] else (0, 0)
        if w >= 1900:
            target = ("<= 8 ms: " + ("met" if d["cpu"] <= 8 else "NOT met"))
        elif 1200 <= w < 1400 and 680 <= h < 800:  # 1280x720 class
            target = ("<= 4 ms: " + ("met" if d["cpu"] <= 4 else "NOT met"))
        else:
            target = ""
        rel = f"{nspx / bench_ns_per_px:.2f}x" if nspx and bench_ns_per_px else "-"
        L.append(f"| {f} | {d['label']} | {d['scale']:.2f} | {ms(d['cpu'])} | "
                 f"{nspx:.1f} | {rel} | {ms(full['cpu']) if full else '-'} | "
                 f"{ms(cv['cpu']) if cv else '-'} | "
                 f"{ratio(d['cpu'], cv['cpu']) if cv else '-'} | {target} |")
    L.append("")
    L.append("Where the default mode's time goes on each real frame (detect()'s own stage "
             "timings, ms per frame, wall clock inside detect()):")
    L.append("")
    L.append("| stage | " + " | ".join(frames) + " |")
    L.append("| --- |" + " ---: |" * len(frames))
    for key, label in REAL_STAGES:
        L.append(f"| {label} | " + " | ".join(
            ms(real[("Detect", f)]["counters"].get(key)) for f in frames) + " |")
    L.append("")
    return L


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--json", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--plot", required=True)
    ap.add_argument("--rss-kb", type=int, default=0)
    ap.add_argument("--commit", default="?")
    ap.add_argument("--stages-by-target", default="",
                    help="profile_core result lines, one per stage and target")
    ap.add_argument("--nodelet", action="append", default=[],
                    help="a result line of bench/measure_nodelet.sh")
    ap.add_argument("--transport", default="",
                    help="results.md of bench/measure_transport.sh (frames on the way in)")
    ap.add_argument("--sequence-cpu", default="",
                    help="profile_core sequence result lines (each frame's CPU time in a loop)")
    a = ap.parse_args()
    ctx, runs = load(a.json)
    if not runs:
        sys.exit("bench_report: no benchmark results in " + a.json)

    L = []
    L.append("# Performance of the detector core")
    L.append("")
    L.append("Generated by `make bench` (scripts/bench.sh, bench/bench_core.cpp) at commit "
             f"`{a.commit}`, {ctx.get('date', '?')}. Do not edit by hand.")
    L.append("")
    load_avg = ctx.get("load_avg", [])
    L.append(f"Machine: {ctx.get('num_cpus', '?')} CPUs at {ctx.get('mhz_per_cpu', '?')} MHz "
             f"(shared), load average at the start {', '.join(f'{x:.2f}' for x in load_avg)}. "
             "All figures are single-threaded (`cv::setNumThreads(1)`), medians of "
             "repetitions (interleaved at random with every other benchmark's, so that the "
             "machine's drift during the run falls on all alike), CPU time per frame; both "
             "implementations ran in the same process and the same run. Frames: generated roads (bench/road_frames.cpp): textured "
             "asphalt around the half-binary threshold, a solid and a dashed marker, a car, "
             "1 mm depth noise, depth holes, the paper's parameters (`Params::paper()`, except where a table says improved), templates adapted "
             "by PCA as in a drive.")
    L.append("")

    L.append("## Whole frame")
    L.append("")
    L.append("| size | detect() ms | OpenCV pipeline ms | ratio | target 8x |")
    L.append("| --- | ---: | ---: | ---: | --- |")
    for w, h in SIZES:
        d, o = get(runs, "BM_Detect", w), get(runs, "BM_OpenCV_Pipeline", w)
        ok = "met" if d and o and o / d >= 8 else "NOT met"
        L.append(f"| {w}x{h} | {ms(d)} | {ms(o)} | {ratio(d, o)} | {ok} |")
    if any(("BM_DetectImproved", w) in runs for w, _ in SIZES):
        L.append("")
        L.append("The package's recommended mode (`Params::improved()`: adaptive threshold, road "
                 "and plane gates, lane model) on the same frames, one thread:")
        L.append("")
        L.append("| size | detect() improved ms | ratio to the OpenCV pipeline | before the "
                 "real-streets stages | within 15% |")
        L.append("| --- | ---: | ---: | ---: | --- |")
        for w, h in SIZES:
            di, o = get(runs, "BM_DetectImproved", w), get(runs, "BM_OpenCV_Pipeline", w)
            before = IMPROVED_RATIO_BEFORE[w]
            ok = "met" if di and o and o / di >= 0.85 * before else "NOT met"
            L.append(f"| {w}x{h} | {ms(di)} | {ratio(di, o)} | {before:.1f}x | {ok} |")
        L.append("")
        L.append("`before`: the improved mode's ratio at commit 085bc57 (docs/PERFORMANCE.md of "
                 "that commit), before the road surface, classification, road edges and lane "
                 "model of the real-streets and lane-model work. Ratios, not milliseconds, are "
                 "compared: the machine's speed changes between sessions, the OpenCV pipeline "
                 "runs in the same process and the same run.")
    if any(("BM_Detect2", w) in runs for w, _ in SIZES):
        L.append("")
        L.append("detect() computes G only where it enters R (M >= tau_G in a match map, about 1% "
                 "of the pixels of these frames; `fusionMask()`), after matching. While "
                 "response/geometric has a subscriber the nodelet asks for G at every pixel "
                 "(`LaneDetector::setFullGeometricMap(true)`); R and the detections are the same "
                 "bits either way (test_lane_detector). That whole map does not depend on M, so "
                 "with the second core (`cv::setNumThreads(2)`) normals and G run next to "
                 "matching as two stripes of `cv::parallel_for_` (`runPair()`). Two threads are "
                 "wall time, so they only mean something when the second core is idle; on a "
                 "shared machine other jobs hold it and the pair can be slower than one thread:")
        L.append("")
        L.append("| size | G only where it enters R, 1 thread ms | whole G, 1 thread ms | "
                 "whole G, 2 threads ms (wall) | ratio of the last to the 1-thread OpenCV "
                 "pipeline |")
        L.append("| --- | ---: | ---: | ---: | ---: |")
        for w, h in SIZES:
            d1 = get(runs, "BM_Detect", w)
            dw = get(runs, "BM_DetectFullG", w)
            d2 = get(runs, "BM_Detect2", w, "real")
            L.append(f"| {w}x{h} | {ms(d1)} | {ms(dw)} | {ms(d2)} | "
                     f"{ratio(d2, get(runs, 'BM_OpenCV_Pipeline', w))} |")
    L.append("")
    L.append("The OpenCV pipeline is stages 1-5 only (no seeds, PCA, tracing or plane), so the "
             "ratios are conservative. detect() includes everything.")
    L.append("")

    targets = ctx.get("simd targets", "").split()
    if targets:
        L.append("## Every SIMD target")
        L.append("")
        L.append("The kernels (src/core/simd.h: Google Highway, dispatched at run time) forced onto "
                 "each target of this machine in turn, paper mode, one thread, the same run as the "
                 "OpenCV pipeline above. SSE4 is 128 bits wide like NEON (the ARM target); "
                 "`scalar` is the plain C++ loops (a build without Highway, or a CPU without any "
                 "vector target). The machine's best target, used by detect() above: "
                 f"{ctx.get('simd best target', '?')}.")
        L.append("")
        want = {"SSE4": 8.0, "AVX2": 10.0}
        L.append("| size | target | detect() ms | OpenCV pipeline ms | ratio | requirement |")
        L.append("| --- | --- | ---: | ---: | ---: | --- |")
        for w, h in SIZES:
            o = get(runs, "BM_OpenCV_Pipeline", w)
            for t in targets:
                d = get(runs, f"BM_DetectOn_{t}", w)
                if t in want:
                    req = (f">= {want[t]:.0f}x: " + ("met" if d and o and o / d >= want[t]
                                                     else "NOT met"))
                elif t.startswith("AVX3"):
                    req = "no slower than before (below)"
                elif t == "scalar":
                    best = get(runs, f"BM_DetectOn_{targets[0]}", w)
                    req = f"{d / best:.1f}x the best target" if d and best else "-"
                else:
                    req = ""
                L.append(f"| {w}x{h} | {t} | {ms(d)} | {ms(o)} | {ratio(d, o)} | {req} |")
        L.append("")
        L.append("Before the portable layer (commit d31d81e: hand-written SSE2/AVX2/AVX-512 "
                 "intrinsics behind three dispatch styles), on this machine, measured with "
                 "bench_core of that commit in the same session as the first run of this table: "
                 "AVX-512 detect() 0.984 ms against the OpenCV pipeline's 10.5 ms at 640x380 "
                 "(10.7x), 4.16 ms against 41.7 ms at 1280x760 (10.0x); its plain path (no AVX2) "
                 "4.95 ms and 20.2 ms (profile_core, CPU time).")
        L.append("")
        if any(get(runs, f"BM_DetectImprovedOn_{t}", SIZES[0][0]) for t in targets):
            L.append("The improved (default) mode (`Params::improved()`) on each target, same run "
                     "and frames. Issue 23 asks >= 15x the OpenCV pipeline at 640x380 on the "
                     "machine's best target and >= 10x on SSE4, the width of the ARM target's "
                     "NEON:")
            L.append("")
            want_improved = {targets[0]: 15.0, "SSE4": 10.0}
            L.append("| size | target | detect() improved ms | OpenCV pipeline ms | ratio | "
                     "requirement (640x380) |")
            L.append("| --- | --- | ---: | ---: | ---: | --- |")
            for w, h in SIZES:
                o = get(runs, "BM_OpenCV_Pipeline", w)
                for t in targets:
                    d = get(runs, f"BM_DetectImprovedOn_{t}", w)
                    req = ""
                    if w == SIZES[0][0] and t in want_improved:
                        req = (f">= {want_improved[t]:.0f}x: " +
                               ("met" if d and o and o / d >= want_improved[t] else "NOT met"))
                    L.append(f"| {w}x{h} | {t} | {ms(d)} | {ms(o)} | {ratio(d, o)} | {req} |")
            L.append("")

    by_target = {}
    if a.stages_by_target:
        for line in open(a.stages_by_target):
            m = re.match(r"(\w+) 640 x\d+ on (\w+): ([0-9.]+) ms CPU", line)
            if m:
                by_target.setdefault(m.group(2), {})[m.group(1)] = float(m.group(3))
    if by_target:
        stages = [("halfbinary", "half-binary"), ("points", "3D points"),
                  ("normals", "normals + G (whole map)"), ("matching", "matching"),
                  ("response", "R"),
                  ("detect", "whole detect()")]
        names = list(by_target)
        L.append("Each stage on each target at 640x380 (bench/profile_core: CPU time per call, "
                 "200 calls, same frame; detect() over four frames), to see where a target "
                 "loses:")
        L.append("")
        L.append("| stage | " + " | ".join(names) + " |")
        L.append("| --- |" + " ---: |" * len(names))
        for key, label in stages:
            L.append(f"| {label} | " + " | ".join(ms(by_target[t].get(key)) for t in names) + " |")
        L.append("")
    L.append("What makes the 128-bit target fast enough. FALS normals + G are arithmetic-bound "
             "(one division and one square root per pixel) and on SSE4 (4 float lanes, the "
             "width of NEON) cost about 2.5x their AVX2 time (the `normals + G` row: the whole "
             "map). detect() no longer computes that whole map: R needs G only where M >= tau_G "
             "(Eq. 3), so matching runs first and the windows are summed and solved only in the "
             "16-column units holding such pixels (`fusionMask()`, "
             "`FalsNormals::computeGeometric(..., mask, G)`; at 640x380 about 1% of the pixels and "
             "2% of the units of these frames). R and the "
             "detections are the same bits as with the whole map (test_lane_detector "
             "GeometricMapOnlyWhereItEntersRChangesNoDetection); the normals stage of detect() "
             "drops from about 40% of its time on SSE4 to a few percent, and matching (integer "
             "sums, then the NCC score with OpenCV's flat-window rule in double) is what remains. "
             "Every target computes the same bits, so no target uses FMA (-ffp-contract=off) or "
             "approximate reciprocals. The scalar path is the per-pixel definition, one lane "
             "where the vector targets have 4 to 16: its NCC scores (a double division and "
             "square root per pixel), integral-image rows and the simple per-pixel stages "
             "(half-binary, points, R) no longer hide behind vectors, hence 4-5x the best target "
             "rather than 2x. Instruction counts before this change "
             "(`valgrind --tool=callgrind --toggle-collect='*measured*' profile_core detect 640 "
             "10 TARGET`, 10 frames; valgrind has no AVX-512, and cannot run libhwy on the VM of "
             "later sessions): before the portable layer (d31d81e) AVX2 106.9 M, baseline/plain "
             "818 M; at 8fdda80 AVX2 116.9 M, SSE4 253 M, scalar 932 M.")
    L.append("")

    if any(("BM_FirstFrame/Prepared", w) in runs for w, _ in SIZES):
        L.append("## First frame")
        L.append("")
        L.append("The first detect() of a new detector (a start, or a resolution change; wall time "
                 "of detect() alone) against the steady state (BM_Detect, CPU time), paper mode, "
                 "one thread, fresh memory each time. "
                 "`prepared`: LaneDetector::prepare(size, intrinsics) ran before it, as the nodelet "
                 "does when a camera_info of a new size or camera arrives; `unprepared`: the "
                 "detector allocates and plans during the first frame.")
        L.append("")
        L.append("| size | steady state ms | first frame, prepared ms | ratio | first frame, "
                 "unprepared ms | ratio |")
        L.append("| --- | ---: | ---: | ---: | ---: | ---: |")
        for w, h in SIZES:
            st = get(runs, "BM_Detect", w)
            p_ = get(runs, "BM_FirstFrame/Prepared", w, "real")  # manual time: detect() alone
            u = get(runs, "BM_FirstFrame/Unprepared", w, "real")
            rp = f"{p_ / st:.2f}x" if p_ and st else "-"
            ru = f"{u / st:.2f}x" if u and st else "-"
            L.append(f"| {w}x{h} | {ms(st)} | {ms(p_)} | {rp} | {ms(u)} | {ru} |")
        L.append("")

    L.append("## Stages")
    L.append("")
    L.append("Each stage on its own (same frame, same run), ours against the OpenCV call it "
             "replaces. Ours computes G in the normals pass, so its G/R row is R alone.")
    L.append("")
    hdr = "| stage | OpenCV | " + " | ".join(f"ours {w} | OpenCV {w} | ratio" for w, _ in SIZES)
    L.append(hdr + " |")
    L.append("| --- | --- |" + " ---: | ---: | ---: |" * len(SIZES))
    for label, ours, cvname, note in STAGES:
        cells = []
        for w, _ in SIZES:
            f, o = get(runs, ours, w), get(runs, cvname, w)
            cells += [ms(f), ms(o), ratio(f, o)]
        L.append(f"| {label} | {note} | " + " | ".join(cells) + " |")
    L.append("")

    L.append("## Where detect() spends its time")
    L.append("")
    L.append("detect()'s own stage timings (ms per frame, wall clock inside detect(), so on a "
             "shared machine they add up to more than its CPU time above). The paper reports 40% "
             "pre-processing (half-binary, points, normals) and 60% response map (matching, "
             "G, R) at about 50 ms per 640x380 frame.")
    L.append("")
    L.append("| stage | " + " | ".join(f"{w}x{h} ms | share" for w, h in SIZES) + " |")
    L.append("| --- |" + " ---: | ---: |" * len(SIZES))
    tot = {w: sum(counters(runs, w).values()) or 1.0 for w, _ in SIZES}
    for key, label in COUNTERS:
        cells = []
        for w, _ in SIZES:
            v = counters(runs, w).get(key)
            cells += [ms(v), f"{100 * v / tot[w]:.0f}%" if v is not None else "-"]
        L.append(f"| {label} | " + " | ".join(cells) + " |")
    groups = [("pre-processing (half-binary, points, normals + G)", COUNTERS[:3]),
              ("response map (matching, R)", COUNTERS[3:5]),
              ("detection (seeds, PCA, tracing, plane)", COUNTERS[5:])]
    for label, members in groups:
        cells = []
        for w, _ in SIZES:
            v = sum(counters(runs, w).get(k, 0.0) for k, _ in members)
            cells += [f"**{ms(v)}**", f"**{100 * v / tot[w]:.0f}%**"]
        L.append(f"| {label} | " + " | ".join(cells) + " |")
    L.append("")
    L.append("![time per stage](performance.png)")
    L.append("")

    L.append("## Same results")
    L.append("")
    L.append("Measured in the same run on every generated frame, detect() against detect() on "
             "the reference stages (`setReferenceStages(true)`: cv::matchTemplate, and FALS "
             "solved per window in double as the method is written), from the same start so "
             "the templates adapt identically.")
    L.append("")
    L.append("| size | max abs(M - matchTemplate) | max abs(R - R ref) | identical detections "
             "| max abs(G - G ref) | G pixels beyond 1e-4 |")
    L.append("| --- | ---: | ---: | ---: | ---: | ---: |")
    for w, h in SIZES:
        k = f"equal {w}x{h} "
        L.append(f"| {w}x{h} | {ctx.get(k + 'max |M - matchTemplate|', '-')} | "
                 f"{ctx.get(k + 'max |R - R reference|', '-')} | "
                 f"{ctx.get(k + 'identical detections', '-')} | "
                 f"{ctx.get(k + 'max |G - G double FALS|', '-')} | "
                 f"{ctx.get(k + 'G pixels beyond 1e-4', '-')} |")
    L.append("")
    L.append("Detections (seeds, PCA angles, traced pixels and 3D points, plane) are compared "
             "exactly; scores within 1e-4. G differs from the double-precision definition by "
             "more than 1e-4 only on a few pixels of the first rows with depth (60 m, where "
             "the window's normal is ill-determined by millimetre depth); R uses G only where "
             "M >= tau_G and stays within 1e-5 there. The unit tests check the same: "
             "test_template_matching (every slope, 1e-4), test_fals_normals (2e-4 rad from "
             "the double definition, windows 3/5/7, holes, resampling; OpenCV's RgbdNormals on "
             "a plane), test_lane_detector (FastStagesGiveTheReferenceResults).")
    L.append("")

    di640 = get(runs, "BM_DetectImproved", 640)
    L.extend(real_frames_section(a.json, di640 * 1e6 / (640 * 380) if di640 else None))

    L.extend(lane_grid_section(a.json))

    # bench_conversions (the nodelet's message reading against cv_bridge): measured once, kept
    L.extend([
        '## ROS conversions (cv_bridge)',
        '',
        "The nodelet reads each synchronised set with `conversions::frameFromMsgs()`: layout checks in 64-bit arithmetic, a `cv::Mat` header on `msg.data` through `msg.step`, intrinsics from P (else K). `bench_conversions` (bench/bench_conversions.cpp) does the same job with `cv_bridge::toCvShare` (passthrough encoding: zero copy too) and with image_geometry's `PinholeCameraModel::fromCameraInfo`, counting heap allocations (operator new) per frame; bgr8 + 16UC1, a 26-character frame_id; medians of 5 repetitions, CPU time, at `i24-ros` on the shared 2-core machine (load average 8):",
        '',
        '| messages | hand-written | cv_bridge | cv_bridge + image_geometry |',
        '| --- | ---: | ---: | ---: |',
        '| 640x380 | 0.13 us, 0 allocations | 9.3 us, 22 allocations | 11.4 us, 22 allocations |',
        '| 1280x760 | 0.13 us, 0 allocations | 11.7 us, 22 allocations | 11.7 us, 22 allocations |',
        '| 640x380, depth in the other byte order | 198 us, 0 allocations (reused buffer) | 318 us, 28 allocations | 312 us, 28 allocations |',
        '',
        "So the hand-written path stays: it is 70-90x faster and keeps the nodelet's steady state free of heap allocations (cv_bridge's `toCvShare` builds its `CvImage`, copies the header and parses the encoding strings, 22 allocations per set). cv_bridge's own checks would not replace ours either: it computes `height * step` in 32 bits and indexes `data[0]` of an empty image. Either way it is a few microseconds of a frame of milliseconds; image_geometry adds nothing for a rectified pinhole camera (fx, fy, cx, cy from P) but the same allocations.",
        "",
    ])

    L.append("## Memory")
    L.append("")
    L.append("- Allocations: test_allocations replaces malloc/calloc/realloc/memalign/"
             "posix_memalign (what operator new and cv::fastMalloc reach) with counting "
             "wrappers: after 8 warm-up frames, 12 more detect() calls make **0** heap "
             "allocations at 640x380 and 1280x760, in the paper and the improved mode, on one "
             "thread and on two; rebuilding the lane grid (`LaneGrid::build()`) from each "
             "frame's lane model makes none either.")
    if a.rss_kb:
        L.append(f"- Peak RSS of a process running detect() at 1280x760 (bench/profile_core, "
                 f"including its four generated frames and its own copy of every stage's "
                 f"output): **{a.rss_kb / 1024:.0f} MB**. The detector's largest buffers are "
                 "FALS's adj(Q) table (24 bytes per pixel of the searched rows, 14 MB at "
                 "1280x760) and the organised points (12 bytes per pixel, 12 MB).")
    if a.nodelet:
        L.append("- The nodelet (bench/measure_nodelet.sh: a generated sequence played into "
                 "LaneDetectorNodelet, paper mode, lane_plane and lane_markings subscribed; its own "
                 "diagnostics give detect() and the callback's time around it, the manager's VmHWM "
                 "its peak RSS; wall times, OpenCV's default threads):")
        for line in a.nodelet:
            L.append(f"  - {line}")
    L.append("")

    L.append("## Frames on the way in")
    L.append("")
    if a.transport and os.path.exists(a.transport):
        L.append("Where the frames of a 15-30 Hz RGB-D stream go between a camera driver (or "
                 "rosbag) and the detector's outputs (bench/measure_transport.sh; how to read it "
                 "and what was found: bench/TRANSPORT.md). Latency is wall time on this shared "
                 "machine: each row carries the load average at its start.")
        L.append("")
        with open(a.transport) as f:
            L.extend(f.read().rstrip("\n").split("\n"))
    else:
        L.append("Not measured in this run (`BENCH_TRANSPORT=0`, no ROS, or no "
                 "../shared/realdata): `bench/measure_transport.sh`, bench/TRANSPORT.md.")
    seq = []
    if a.sequence_cpu and os.path.exists(a.sequence_cpu):
        pat = (r"sequence (\S+) \(.*?, (\d+) frames in a loop, scale ([0-9.]+)\) x(\d+) on (\w+): "
               r"CPU ms per frame mean ([0-9.]+) p50 ([0-9.]+) p99 ([0-9.]+) max ([0-9.]+) .*?"
               r"costliest frame of the loop \(median over the passes\) (\d+): ([0-9.]+) ms")
        for line in open(a.sequence_cpu):
            m = re.search(pat, line)
            if m:
                seq.append(m.groups())
    if seq:
        L.append("")
        L.append("The same frames without ROS (`profile_core sequence WIDTHxHEIGHT N`: one "
                 "detector over the looped drive as the player sends it, default mode, one thread, "
                 "each frame's CPU time of its thread after one pass of warm-up). The costliest "
                 "frame of the loop, by its median over the passes, is what the scene asks for; "
                 "p99 above it is the machine (other processes' cache and memory traffic, the "
                 "virtual CPU's neighbours), which the callback's wall time then adds its waits to:")
        L.append("")
        L.append("| size | frames x passes | scale | mean ms | p50 ms | p99 ms | max ms | p99 / mean "
                 "| costliest frame's median ms | / mean |")
        L.append("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        for size, frames, scale, n, target, mean, p50, p99, mx, k, kms in seq:
            mean_f = float(mean)
            L.append(f"| {size} | {frames} x {int(n) // int(frames)} | {float(scale):.2f} | "
                     f"{mean_f:.2f} | {float(p50):.2f} | {float(p99):.2f} | {float(mx):.2f} | "
                     f"{float(p99) / mean_f:.2f} | {float(kms):.2f} | "
                     f"{float(kms) / mean_f:.2f} |")
    L.append("")

    L.append("## How the core gets there")
    L.append("")
    L.append("- **Matching** (template_matching.cpp): a line template is one run per row, "
             "drawn at a rational slope p/q (q <= 8, within half a pixel of the requested line). "
             "Run ends clipped by the square are vertical ranges of the integral image; the "
             "others repeat every q rows shifted by p columns and are summed as residue chains "
             "of a running sum along the slope: 8 lookups per pixel at 45 degrees, 4 + 4q in "
             "general, independent of the template size. Window sums and energies come from "
             "integral images; all sums are exact integers (mod 2^32; a window's energy is "
             "unsigned, up to 65536 x 255^2 for the largest template). Rows are produced in a "
             "ring (one fused prefix-scan pass) and scored with OpenCV's flat-window rule.")
    L.append("- **FALS** (fals_normals.cpp): M = B Q B^T, b = B s in the basis "
             "B = [w_centre, e_x/fx, e_y/fy], where Q = sum k (1,du,dv)(1,du,dv)^T is nearly "
             "diagonal (M's condition number is about 1e5). adj(Q) of whole windows is "
             "precomputed in double; s is a separable box/moment filter of k/z. Windows with "
             "missing depth use their own moments (float when well conditioned, exact double "
             "otherwise). G (Eq. 2) is written in the same pass; normals only when the road "
             "gate needs them. detect() runs it after matching and only in the 16-column units "
             "where some match map has M >= tau_G (Eq. 3 adds G only there): the rows a window "
             "reads are prepared, summed and solved only over those units and their "
             "neighbours.")
    L.append("- **Half-binary, points, R, seeds, tracing boxes**: kernels that reproduce the "
             "scalar definitions bit for bit (OpenCV's fixed-point grey, the double depth decode, "
             "cv::minMaxLoc's first maximum, exact integer box sums).")
    L.append("- **One SIMD layer** (src/core/simd.h): every hot kernel is written once with Google "
             "Highway and compiled for each target of the architecture (x86: SSE4, AVX2, "
             "AVX-512; aarch64: NEON), the best one the CPU has chosen at run time "
             "(HWY_DYNAMIC_DISPATCH); the scalar target is the plain per-pixel loops, also the "
             "definitions every lane follows and the loops' tails. No -march, no -ffast-math, "
             "-ffp-contract=off (no FMA): every target gives the same bits "
             "(test_lane_detector, EveryTargetGivesTheSameBits, forces each target of the "
             "machine). Without libhwy-dev (Ubuntu 20.04) the build has the scalar target only.")
    L.append("- Steady state allocates nothing: buffers only grow, no cv::Mat::setTo (it allocates "
             "a scratch buffer per call), the second core through cv::parallel_for_ (OpenCV's "
             "TBB pool, no allocation per call).")
    L.append("- **aarch64**: `make test-arm64` cross-compiles the core, its gtests and "
             "profile_core/bench_disparity with g++-aarch64-linux-gnu against Debian's arm64 "
             "libraries and runs the gtests under qemu-aarch64, NEON and scalar targets, and "
             "compares detect() on a fixed drive with this machine's (test_golden_detections: "
             "counts, flags and kinds exact, pixels within 1e-4 px, points within 1e-5 m, the "
             "plane (normal and offset), normals and angles within 1e-6, scores within 1e-5). "
             "Timings under "
             "emulation are not speed figures: no ARM figure is given here.")
    L.append("")
    L.append("For decisions on this shared 2-core machine use instruction counts, which do not "
             "depend on the other jobs: `valgrind --tool=callgrind --toggle-collect='*measured*' "
             "profile_core detect 640 4` (bench/profile_core.cpp runs a stage a fixed number of "
             "times).")
    L.append("")
    with open(a.out, "w") as f:
        f.write("\n".join(L))
    plot(runs, a.plot)


if __name__ == "__main__":
    main()
