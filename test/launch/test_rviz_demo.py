#!/usr/bin/env python3
"""rviz on a running demo, for real: screenshot under Xvfb, check that the displays drew.

1. renders a short synthetic sequence (tools/generate_sequence) and converts it to a bag
   (tools/sequence_to_bag, with the base_link tf), unless --bag is given;
2. starts Xvfb (software GL through Mesa) with its framebuffer in a file (-fbdir), and
   launch/demo.launch on its own master port: the bag looping through the nodelet and rviz with
   the shipped rviz/lane_detector.rviz (and --gl-guard preloaded into rviz: Mesa's software GL
   sizes a window the X server does not know from garbage, docs/RELIABILITY.md);
3. finds rviz's render windows (the Ogre views are native X windows: xwininfo -tree), reads the
   framebuffer (XWD format) and checks, until all pass or the time limit:
   - the overlay image panel shows a picture (many distinct colours, few black pixels),
   - both response map panels show bright response ridges,
   - the 3D view shows the lane points (the point cloud's magenta / cyan squares), the lane
     grid (the Map display of lane_grid: its unknown cells, 0x708986 at alpha 0.5, blend
     grey-green into the background) and the grid over the background;
4. writes a JUnit result (--xunit) and the screenshot (--screenshot), stops what it started.
rviz dying at any point is a test error (with the tail of its log). Exit status 0 when every
check passed.
"""
import argparse
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time
from xml.sax.saxutils import escape

import numpy as np

try:
    import cv2
except ImportError:  # only needed to write the PNG
    cv2 = None

BACKGROUND = np.array([48, 48, 48])  # rviz background of the shipped config (RGB)
POINT_COLOURS = [np.array([255, 0, 255]), np.array([0, 255, 255])]  # left, right lane points
# lane_grid's unknown cells in the Map display (costmap scheme, alpha 0.5) over the background
GRID_UNKNOWN = (0.5 * np.array([0x70, 0x89, 0x86]) + 0.5 * BACKGROUND).astype(int)


def free_port():
    s = socket.socket()
    s.bind(("localhost", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def read_xwd(path):
    """RGB image of an XWD file (the Xvfb -fbdir framebuffer, 24/32 bit TrueColor)."""
    with open(path, "rb") as f:
        data = f.read()
    (header_size, _version, _fmt, _depth, width, height, _xoff, byte_order, _unit, _bit_order, _pad,
     bits_per_pixel, bytes_per_line, _vclass, red_mask, _green_mask, blue_mask, _bits_per_rgb,
     _cmap_entries, ncolors) = struct.unpack(">20I", data[:80])
    if bits_per_pixel != 32:
        raise RuntimeError("unsupported XWD: %d bits per pixel" % bits_per_pixel)
    offset = header_size + 12 * ncolors
    rows = np.frombuffer(data, np.uint8, bytes_per_line * height, offset).reshape(height, bytes_per_line)
    px = rows[:, :4 * width].reshape(height, width, 4)
    if byte_order != 0:  # MSBFirst: X R G B
        px = px[:, :, ::-1]
    bgr = px[:, :, :3]  # LSBFirst: B G R X
    if red_mask == 0xff and blue_mask == 0xff0000:
        bgr = bgr[:, :, ::-1]
    return bgr[:, :, ::-1].copy()  # RGB


def render_windows(display):
    """Leaf X windows of rviz at depth >= 3 (Ogre render panels): list of (x, y, w, h)."""
    out = subprocess.run(["xwininfo", "-root", "-tree", "-display", display], capture_output=True,
                         text=True, timeout=10).stdout
    windows, in_rviz, rviz_indent = [], False, 0
    lines = out.splitlines()
    for i, line in enumerate(lines):
        m = re.match(r"^(\s*)0x[0-9a-f]+ (.*?)\s+(\d+)x(\d+)\+(-?\d+)\+(-?\d+)\s+\+(-?\d+)\+(-?\d+)\s*$", line)
        if not m:
            continue
        indent = len(m.group(1))
        if "RViz" in m.group(2):
            in_rviz, rviz_indent = True, indent
            continue
        if in_rviz and indent <= rviz_indent:
            in_rviz = False
        if not in_rviz:
            continue
        depth = (indent - rviz_indent) // 3
        w, h, x, y = int(m.group(3)), int(m.group(4)), int(m.group(7)), int(m.group(8))
        nxt = lines[i + 1] if i + 1 < len(lines) else ""
        has_children = "child" in nxt
        if depth >= 2 and not has_children and w >= 200 and h >= 150:
            windows.append((x, y, w, h))
    return windows


def log_tail(log_path, lines=6):
    with open(log_path, errors="replace") as f:
        text = [l.strip() for l in f.read().replace("\r", "\n").splitlines() if l.strip() and "RUNNING" not in l]
    return " | ".join(text[-lines:])


def rviz_died(log_path):
    with open(log_path, errors="replace") as f:
        return re.search(r"\[rviz-\d+\] process has died", f.read()) is not None


def near(img, colour, tol):
    return np.all(np.abs(img.astype(int) - colour) <= tol, axis=2)


def check(shot, windows):
    """Check results: list of (name, passed, detail)."""
    results = []
    if len(windows) < 4:
        return [("rviz render panels", False, "found %d render windows, expected the 3D view and 3 image panels"
                 % len(windows))]
    windows = sorted(windows, key=lambda r: r[2] * r[3], reverse=True)
    view, images = windows[0], sorted(windows[1:4], key=lambda r: r[0])

    def crop(r):
        x, y, w, h = r
        return shot[y:y + h, x:x + w]

    # overlay: a photo-like picture (the road scene and the drawn markers)
    ov = crop(images[0])
    quantised = (ov // 8).reshape(-1, 3)
    colours = len(np.unique(quantised[:, 0] * 1024 + quantised[:, 1] * 32 + quantised[:, 2]))
    lit = np.mean(ov.max(axis=2) > 20)
    results.append(("overlay image panel (debug_image)", colours > 300 and lit > 0.3,
                    "%d distinct colours, %.0f%% non-black" % (colours, 100 * lit)))
    # response maps: bright ridges on black
    for name, r in (("response R left panel", images[1]), ("response R right panel", images[2])):
        bright = int(np.sum(crop(r).max(axis=2) > 100))
        results.append((name, bright > 150, "%d bright pixels" % bright))
    # 3D view: lane points (flat squares in the point cloud's colours) and the grid
    v = crop(view)
    points = int(sum(np.sum(near(v, c, 40)) for c in POINT_COLOURS))
    results.append(("3D view: lane points (PointCloud2)", points > 40, "%d magenta/cyan pixels" % points))
    grid = int(np.sum(near(v, GRID_UNKNOWN, 12)))
    results.append(("3D view: lane grid (Map of lane_grid)", grid > 2000,
                    "%d grey-green pixels" % grid))
    drawn = float(np.mean(np.any(np.abs(v.astype(int) - BACKGROUND) > 12, axis=2)))
    results.append(("3D view: grid and markers over the background", drawn > 0.01,
                    "%.1f%% of the view differs from the background" % (100 * drawn)))
    return results


def write_xunit(path, results, elapsed, error=None):
    if not path:
        return
    cases = []
    for name, ok, detail in results:
        body = "" if ok else '<failure message="%s"/>' % escape(detail, {'"': "&quot;"})
        cases.append('  <testcase classname="rviz_demo" name="%s" time="0">%s<system-out>%s</system-out></testcase>'
                     % (escape(name, {'"': "&quot;"}), body, escape(detail)))
    if error:
        cases.append('  <testcase classname="rviz_demo" name="setup" time="0"><error message="%s"/></testcase>'
                     % escape(error, {'"': "&quot;"}))
    failures = sum(1 for _, ok, _ in results if not ok)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as f:
        f.write('<?xml version="1.0" encoding="utf-8"?>\n<testsuite name="rviz_demo" tests="%d" failures="%d" '
                'errors="%d" time="%.1f">\n%s\n</testsuite>\n'
                % (len(cases), failures, 1 if error else 0, elapsed, "\n".join(cases)))


class Processes:
    """Processes started in their own process group; stop() ends them in reverse order."""

    def __init__(self):
        self.procs = []

    def start(self, cmd, log, env=None, **kw):
        p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=env,
                             start_new_session=True, **kw)
        self.procs.append(p)
        return p

    @staticmethod
    def end(p):
        if p.poll() is not None:
            return
        for sig, wait in ((signal.SIGINT, 10), (signal.SIGTERM, 5), (signal.SIGKILL, 5)):
            try:
                os.killpg(p.pid, sig)
            except ProcessLookupError:
                return
            try:
                p.wait(wait)
                return
            except subprocess.TimeoutExpired:
                pass

    def stop(self):
        for p in reversed(self.procs):
            self.end(p)
        self.procs = []


def make_bag(tools, work, frames):
    seq, bag = os.path.join(work, "sequence"), os.path.join(work, "demo.bag")
    subprocess.run([os.path.join(tools, "generate_sequence"), "--scenario", "summer", "--frames", str(frames),
                    "--out", seq, "--quiet", "--skip-if-same"], check=True, timeout=300)
    if not os.path.exists(bag) or os.path.getmtime(bag) < os.path.getmtime(os.path.join(seq, "scenario.json")):
        subprocess.run([os.path.join(tools, "sequence_to_bag"), "--dataset", seq, "--out", bag + ".tmp", "--quiet",
                        "--tf-parent", "base_link", "--tf-z", "1.5", "--tf-pitch", "3"], check=True, timeout=300)
        os.replace(bag + ".tmp", bag)
    return bag


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.normpath(os.path.join(here, "..", ".."))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--launch", default=os.path.join(root, "launch", "demo.launch"), help="demo launch file")
    ap.add_argument("--bag", help="bag to play (default: render --frames synthetic frames)")
    ap.add_argument("--tools", help="folder of generate_sequence and sequence_to_bag (needed without --bag)")
    ap.add_argument("--frames", type=int, default=60, help="frames of the generated sequence")
    ap.add_argument("--work", default=None, help="work folder (sequence, bag, logs); default: a temporary one")
    ap.add_argument("--screenshot", help="write the checked screenshot here (PNG)")
    ap.add_argument("--xunit", help="JUnit result file")
    ap.add_argument("--timeout", type=float, default=90.0, help="seconds to wait for rviz to draw everything")
    ap.add_argument("--gl-guard", help="library preloaded into rviz (tools/rviz/gl_drawable_guard.cpp)")
    args = ap.parse_args()

    t0 = time.time()
    work = args.work or tempfile.mkdtemp(prefix="rviz_demo_")
    os.makedirs(work, exist_ok=True)
    procs = Processes()
    results, error, shot = [], None, None
    fbdir = tempfile.mkdtemp(prefix="xvfb_fb_")
    try:
        if args.bag:
            bag = args.bag
        elif args.tools:
            bag = make_bag(args.tools, work, args.frames)
        else:
            raise RuntimeError("give --bag or --tools")

        # Xvfb: its own display number (-displayfd), framebuffer mapped to fbdir/Xvfb_screen0
        read_fd, write_fd = os.pipe()
        procs.start(["Xvfb", "-displayfd", str(write_fd), "-screen", "0", "1280x1024x24", "-fbdir", fbdir,
                     "-nolisten", "tcp", "-nocursor"], open(os.path.join(work, "xvfb.log"), "w"), pass_fds=(write_fd,))
        os.close(write_fd)
        with os.fdopen(read_fd) as f:
            number = f.readline().strip()
        if not number:
            raise RuntimeError("Xvfb did not start (log: %s)" % os.path.join(work, "xvfb.log"))
        display = ":" + number

        deadline = time.time() + args.timeout
        port = free_port()
        env = dict(os.environ, DISPLAY=display, ROS_MASTER_URI="http://localhost:%d" % port,
                   ROS_HOSTNAME="localhost", ROS_LOG_DIR=os.path.join(work, "ros_log"))
        env.pop("ROS_IP", None)
        log_path = os.path.join(work, "demo_launch.log")
        command = ["roslaunch", "-p", str(port), args.launch, "bag:=" + bag, "loop:=true"]
        if args.gl_guard:  # Mesa's software GL sizes a missing window from garbage (RELIABILITY.md)
            if not os.path.exists(args.gl_guard):
                raise RuntimeError("--gl-guard %s does not exist" % args.gl_guard)
            command.append("rviz_prefix:=env LD_PRELOAD=" + args.gl_guard)
        launch = procs.start(command, open(log_path, "w"), env=env)
        while True:
            if launch.poll() is not None:
                raise RuntimeError("roslaunch exited (log: %s): %s" % (log_path, log_tail(log_path)))
            if rviz_died(log_path):
                raise RuntimeError("rviz died (log: %s): %s" % (log_path, log_tail(log_path)))
            windows = render_windows(display)
            fb = os.path.join(fbdir, "Xvfb_screen0")
            shot = read_xwd(fb)
            results = check(shot, windows)
            if all(ok for _, ok, _ in results) or time.time() > deadline:
                break
            time.sleep(2.0)
    except Exception as e:  # setup failures are test errors, with the reason
        error = "%s: %s" % (type(e).__name__, e)
    finally:
        procs.stop()
        shutil.rmtree(fbdir, ignore_errors=True)

    if shot is not None and args.screenshot and cv2 is not None:
        os.makedirs(os.path.dirname(os.path.abspath(args.screenshot)), exist_ok=True)
        cv2.imwrite(args.screenshot, shot[:, :, ::-1])
    elapsed = time.time() - t0
    write_xunit(args.xunit, results, elapsed, error)
    for name, ok, detail in results:
        print("%s %s: %s" % ("PASS" if ok else "FAIL", name, detail))
    if error:
        print("ERROR %s" % error)
    passed = not error and results and all(ok for _, ok, _ in results)
    print("rviz demo test: %s in %.0f s%s" % ("passed" if passed else "FAILED", elapsed,
                                               (", screenshot " + args.screenshot) if args.screenshot else ""))
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
