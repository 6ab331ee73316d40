#!/usr/bin/env python3
"""Soak test of the LaneDetectorNodelet running in a nodelet manager (tools/soak/soak.launch).

Replays the frames of a rosbag (tools' generate_sequence / sequence_to_bag) in a loop at a
steady rate, re-stamped with a fresh time (monotonic, as a live camera), for --frames frames,
while parameters change through dynamic_reconfigure, output subscribers come and go (including
periods with none, when the nodelet unsubscribes its inputs) and bad frames are injected. It
monitors the manager process (alive, RSS every second), every output message (NaN/inf) and the
nodelet's diagnostics (frame accounting), then prints PASS/FAIL per check, writes
<report-dir>/soak_report.json and soak_report.md, and exits non-zero on FAIL.

Run by scripts/soak.sh (`make soak`), and as the rostest test/ros/soak_short.test (a few hundred
frames; --generate-frames makes its own small bag).

Accounting rule (colour frames; the soak is the only publisher of the inputs):
  nodelet, at every diagnostics update:
      received == processed + sum(dropped by reason) + skipped + not synchronised + waiting
  soak vs nodelet, at the end:
      sent = colour frames published while the nodelet was connected (rospy's header.seq count)
      edge = sent - (received + lost before the nodelet)
      0 <= edge <= cycles * (queue_size + rate * 0.5 s), cycles = input subscribe periods:
      the frames in flight or in the nodelet's subscriber queue when it unsubscribes (and any
      lost before the first one received after it subscribes) are seen by neither counter.
RSS (manager, /proc/<pid>/status every second): median over the second half of a reference
window (start configuration, every output subscribed, no churn; ~10 s) right after the warm-up
(the first 10 % of the frames, with churn) against the same window at the end of the run.
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile
import threading
import time
import warnings
import xmlrpc.client

import numpy as np

import dynamic_reconfigure.client
import rosbag
import rosgraph
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from nodelet.srv import NodeletList, NodeletUnload
from sensor_msgs.msg import CameraInfo, Image, PointCloud2
from visualization_msgs.msg import MarkerArray

from rgbd_lane_detector.msg import LaneMarkings, LanePlane

OUTPUTS = {
    'lane_plane': LanePlane,
    'lane_markings': LaneMarkings,
    'lane_points': PointCloud2,
    'lane_visualization': MarkerArray,
    'response/left': Image,
    'response/right': Image,
    'response/geometric': Image,
    'debug_image': Image,
}
BAD_KINDS = ['wrong_encoding', 'depth_size_mismatch', 'nan_depth', 'zero_depth', 'missing_camera_info']
BOOL_PARAMS = ['adaptive_tau_c', 'use_depth', 'adapt_templates', 'ego_lane_seeds', 'road_gate', 'snap_to_plane',
               'report_only_complete', 'track_lanes']
# name: (low, high) within the .cfg range, chosen so every combination runs at camera rate
NUMERIC_PARAMS = {
    'tau_c': (5, 60), 'tau_c_offset': (0, 30), 'processing_scale': (0.4, 1.0), 'roi_top': (0.3, 0.6),
    'roi_bottom': (0.8, 1.0), 'normal_window': (3, 11), 'template_size': (8, 40),
    'template_line_width': (1, 8), 'template_angle_deg': (0.0, 80.0), 'depth_threshold': (0.0, 1.0),
    'alpha': (0.0, 2.0), 'beta': (0.0, 2.0), 'depth_term': (0, 1), 'tau_g': (0.0, 1.0),
    'pca_threshold': (0.0, 1.0), 'jump_step': (2, 20), 'plane_fit': (0, 1), 'fill_depth_holes': (0, 5),
    'gap_steps': (0, 5), 'plane_smoothing': (0.0, 0.9),
}


def log(msg):
    print('[soak] ' + msg, flush=True)


def non_finite(values):
    """Number of NaN/inf among a list of floats."""
    return sum(1 for v in values if not math.isfinite(v))


class Monitor:
    """Output and diagnostics callbacks (rospy threads): counts, NaN checks, accounting."""

    def __init__(self):
        self.lock = threading.Lock()
        self.messages = {t: 0 for t in OUTPUTS}
        self.nan = {t: 0 for t in OUTPUTS}
        self.nan_examples = []
        self.diag = None          # latest processing key/values
        self.diag_time = None     # wall time of the latest report
        self.reports = 0
        self.violations = 0
        self.violation_examples = []

    def _nan(self, topic, count, what):
        if count:
            with self.lock:
                self.nan[topic] += count
                if len(self.nan_examples) < 10:
                    self.nan_examples.append('%s: %d non-finite %s' % (topic, count, what))

    def output(self, msg, topic):
        with self.lock:
            self.messages[topic] += 1
        if isinstance(msg, LanePlane):
            n = msg.normal
            vals = [n.x, n.y, n.z, msg.distance, msg.left_score, msg.right_score, msg.rms_error]
            vals += [c for p in msg.support_points for c in (p.x, p.y, p.z)]
            self._nan(topic, non_finite(vals), 'plane values (valid=%s)' % msg.valid)
        elif isinstance(msg, LaneMarkings):
            vals = [msg.left_score, msg.right_score, msg.left_angle, msg.right_angle]
            vals += [c for p in msg.left + msg.right for c in (p.x, p.y, p.z)]
            self._nan(topic, non_finite(vals), 'marking values')
        elif isinstance(msg, PointCloud2):
            floats = [f for f in msg.fields if f.datatype in (7, 8)]  # FLOAT32, FLOAT64
            if msg.width * msg.height and floats:
                dtype = np.dtype({'names': [f.name for f in floats],
                                  'formats': ['<f4' if f.datatype == 7 else '<f8' for f in floats],
                                  'offsets': [f.offset for f in floats], 'itemsize': msg.point_step})
                pts = np.frombuffer(msg.data, dtype=dtype, count=msg.width * msg.height)
                self._nan(topic, int(sum(np.count_nonzero(~np.isfinite(pts[f.name])) for f in floats)),
                          'cloud fields')
        elif isinstance(msg, MarkerArray):
            vals = []
            for m in msg.markers:
                p, q, s = m.pose.position, m.pose.orientation, m.scale
                vals += [p.x, p.y, p.z, q.x, q.y, q.z, q.w, s.x, s.y, s.z]
                vals += [c for pt in m.points for c in (pt.x, pt.y, pt.z)]
            self._nan(topic, non_finite(vals), 'marker values')
        elif isinstance(msg, Image) and msg.encoding == '32FC1':
            data = np.frombuffer(msg.data, dtype='<f4' if not msg.is_bigendian else '>f4')
            self._nan(topic, int(np.count_nonzero(~np.isfinite(data))), 'response values')

    def diagnostics(self, msg):
        for status in msg.status:
            if 'processing' not in status.name:
                continue
            v = {kv.key: kv.value for kv in status.values}
            if 'Frames received' not in v:
                continue
            ok, text = accounting_holds(v)
            with self.lock:
                self.diag = v
                self.diag_time = time.time()
                self.reports += 1
                if not ok:
                    self.violations += 1
                    if len(self.violation_examples) < 5:
                        self.violation_examples.append(text)


def counter(v, key):
    return int(v.get(key, '0'))


def drop_reasons(v):
    return {k[len('Dropped: '):]: int(x) for k, x in v.items() if k.startswith('Dropped: ')}


def accounting_holds(v):
    """The nodelet's rule on one diagnostics report."""
    r = {k: counter(v, k) for k in ('Frames received', 'Frames processed', 'Frames dropped',
                                   'Frames skipped (no subscriber)', 'Frames not synchronised',
                                   'Frames waiting', 'Frames unaccounted')}
    by_reason = sum(drop_reasons(v).values())
    total = (r['Frames processed'] + r['Frames dropped'] + r['Frames skipped (no subscriber)'] +
             r['Frames not synchronised'] + r['Frames waiting'])
    ok = r['Frames received'] == total and by_reason == r['Frames dropped'] and r['Frames unaccounted'] == 0
    return ok, 'received %d vs %d (processed+dropped+skipped+not sync+waiting), dropped %d vs by reason %d' % (
        r['Frames received'], total, r['Frames dropped'], by_reason)


def load_frames(bag_path, ns):
    """(colour, depth, info) triples of the bag, in stamp order."""
    topics = {ns + '/rgb/image_rect_color': 0, ns + '/depth_registered/image_rect': 1, ns + '/rgb/camera_info': 2}
    sets = {}
    with rosbag.Bag(bag_path) as bag:
        for topic, msg, _ in bag.read_messages(topics=list(topics)):
            sets.setdefault(msg.header.stamp.to_nsec(), [None, None, None])[topics[topic]] = msg
    frames = [tuple(s) for _, s in sorted(sets.items()) if all(m is not None for m in s)]
    if not frames:
        raise RuntimeError('no complete frame in %s (topics %s)' % (bag_path, ', '.join(topics)))
    return frames


def make_bad_frames(frame):
    """Bad variants of one good (colour, depth, info): kind -> (colour, depth or None, info or None)."""
    colour, depth, info = frame
    depth_mm = np.frombuffer(depth.data, dtype='<u2').reshape(depth.height, depth.width) \
        if depth.encoding == '16UC1' else None

    def image(like, encoding, array):
        m = Image(header=like.header, height=array.shape[0], width=array.shape[1], encoding=encoding,
                  is_bigendian=0, step=array.shape[1] * array.itemsize)
        m.data = array.tobytes()
        return m

    wrong = Image(header=colour.header, height=colour.height, width=colour.width, encoding='rgb16',
                  is_bigendian=colour.is_bigendian, step=colour.step, data=colour.data)
    half = depth_mm[::2, ::2].copy() if depth_mm is not None else np.zeros((depth.height // 2, depth.width // 2),
                                                                          dtype='<u2')
    return {
        'wrong_encoding': (wrong, depth, info),
        'depth_size_mismatch': (colour, image(depth, '16UC1', half), info),
        'nan_depth': (colour, image(depth, '32FC1', np.full((depth.height, depth.width), np.nan, dtype='<f4')),
                      info),
        'zero_depth': (colour, image(depth, '16UC1', np.zeros((depth.height, depth.width), dtype='<u2')), info),
        'missing_camera_info': (colour, depth, None),
    }


def find_tool(name):
    import roslib.packages
    paths = roslib.packages.find_node('rgbd_lane_detector', name)
    if not paths:
        raise RuntimeError('%s not found (build the workspace and source its setup.bash)' % name)
    return paths[0]


def generate_bag(frames, width, height, out_dir):
    bag = os.path.join(out_dir, 'soak_short.bag')
    subprocess.check_call([find_tool('generate_sequence'), '--scenario', 'summer', '--frames', str(frames),
                           '--width', str(width), '--height', str(height), '--out', os.path.join(out_dir, 'seq'),
                           '--bag', bag, '--quiet'])
    return bag


def unload_nodelet(manager, node):
    """Unload node from manager; True when the manager no longer lists it."""
    try:
        rospy.wait_for_service(manager + '/unload_nodelet', timeout=30)
        if not rospy.ServiceProxy(manager + '/unload_nodelet', NodeletUnload)(name=node).success:
            log('unload_nodelet %s failed' % node)
            return False
        return wait_until(lambda: node not in rospy.ServiceProxy(manager + '/list', NodeletList)().nodelets,
                          30.0)
    except (rospy.ROSException, rospy.ServiceException) as e:
        log('unloading %s: %s' % (node, e))
        return False


def node_pid(name):
    uri = rosgraph.Master('/soak').lookupNode(name)
    code, _, pid = xmlrpc.client.ServerProxy(uri).getPid('/soak')
    if code != 1:
        raise RuntimeError('getPid of %s failed' % name)
    return int(pid)


def rss_kb(pid):
    try:
        with open('/proc/%d/status' % pid) as f:
            for line in f:
                if line.startswith('VmRSS:'):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def wait_until(cond, timeout, period=0.05):
    end = time.time() + timeout
    while time.time() < end and not rospy.is_shutdown():
        if cond():
            return True
        time.sleep(period)
    return cond()


class Soak:
    def __init__(self, args):
        self.a = args
        self.rng = random.Random(args.seed)  # frames; the churn threads have their own
        self.rng_sub = random.Random(args.seed + 1)
        self.rng_param = random.Random(args.seed + 2)
        self.stop = threading.Event()
        self.paused = threading.Event()  # reference windows: no churn
        self.churn_lock = threading.Lock()
        self.mon = Monitor()
        self.subs = {}
        self.subs_lock = threading.Lock()
        self.sub_changes = 0
        self.none_periods = 0
        self.param_changes = 0
        self.param_resets = 0
        self.param_errors = 0
        self.published = 0
        self.rss = []  # (wall time, frames published, kB)
        self.alive = True
        self.pid = None

    # --- churn threads -------------------------------------------------------------------------
    def set_subscribers(self, topics):
        with self.subs_lock:
            for t in list(self.subs):
                if t not in topics:
                    self.subs.pop(t).unregister()
            for t in topics:
                if t not in self.subs:
                    self.subs[t] = rospy.Subscriber(self.a.ns + '/' + t, OUTPUTS[t], self.mon.output,
                                                    callback_args=t, queue_size=5, buff_size=2 ** 24)

    def subscriber_churn(self):
        rng = self.rng_sub
        while not self.stop.wait(rng.uniform(self.a.sub_period * 0.5, self.a.sub_period * 1.5)):
            with self.churn_lock:
                if self.paused.is_set():
                    continue
                if self.sub_changes % 4 == 1:  # every 4th change: no subscriber at all
                    topics = []
                    self.none_periods += 1
                else:
                    topics = rng.sample(list(OUTPUTS), rng.randint(1, len(OUTPUTS)))
                self.set_subscribers(topics)
                self.sub_changes += 1

    def random_config(self, descriptions):
        rng = self.rng_param
        names = [d['name'] for d in descriptions]
        chosen = rng.sample([n for n in BOOL_PARAMS + list(NUMERIC_PARAMS) if n in names], rng.randint(1, 4))
        types = {d['name']: d['type'] for d in descriptions}
        config = {}
        for name in chosen:
            if name in BOOL_PARAMS:
                config[name] = rng.random() < 0.5
            else:
                lo, hi = NUMERIC_PARAMS[name]
                config[name] = rng.randint(lo, hi) if types[name] == 'int' else round(rng.uniform(lo, hi), 3)
        return config

    def parameter_churn(self, client, initial):
        descriptions = client.get_parameter_descriptions()
        rng = self.rng_param
        while not self.stop.wait(rng.uniform(self.a.param_period * 0.5, self.a.param_period * 1.5)):
            with self.churn_lock:
                if self.paused.is_set():
                    continue
                reset = self.param_changes % 10 == 9  # back to the start configuration now and then
                config = initial if reset else self.random_config(descriptions)
                try:
                    client.update_configuration(config)
                    self.param_changes += 1
                    self.param_resets += reset
                except Exception as e:  # noqa: BLE001 - counted, the soak goes on
                    self.param_errors += 1
                    log('reconfigure failed: %s' % e)

    def reference_state(self, client, initial):
        """Churn paused; start configuration, every output subscribed (the RSS reference windows)."""
        self.paused.set()
        with self.churn_lock:
            try:
                client.update_configuration(initial)
            except Exception as e:  # noqa: BLE001
                self.param_errors += 1
                log('reconfigure failed: %s' % e)
            self.set_subscribers(list(OUTPUTS))

    def rss_sampler(self):
        while not self.stop.is_set():
            kb = rss_kb(self.pid)
            if kb is None:
                self.alive = False
                log('manager process %d is gone' % self.pid)
                return
            self.rss.append((time.time(), self.published, kb))
            self.stop.wait(1.0)

    # --- main ------------------------------------------------------------------------------------
    def run(self):
        a = self.a
        t_start = time.time()
        frames = load_frames(a.bag, a.ns)
        bad = make_bad_frames(frames[0])
        log('%d frames from %s (%dx%d), replaying %d at %.0f Hz' % (len(frames), a.bag, frames[0][0].width,
                                                                     frames[0][0].height, a.frames, a.rate))
        # queue_size None: publish() writes to the socket itself, so every frame counted as sent
        # reached the nodelet's connection (rospy warns about it: silenced)
        warnings.filterwarnings('ignore', message='The publisher should be created with an explicit')
        pub_c = rospy.Publisher(a.ns + '/rgb/image_rect_color', Image, queue_size=None)
        pub_d = rospy.Publisher(a.ns + '/depth_registered/image_rect', Image, queue_size=None)
        pub_i = rospy.Publisher(a.ns + '/rgb/camera_info', CameraInfo, queue_size=None)
        rospy.Subscriber('/diagnostics', DiagnosticArray, self.mon.diagnostics, queue_size=50)

        node = a.ns + '/' + a.node
        manager = a.ns + '/' + a.manager
        if not wait_until(lambda: self._lookup(manager) and self._lookup(node), 30.0):
            raise RuntimeError('%s / %s not running' % (manager, node))
        self.pid = node_pid(manager)
        client = dynamic_reconfigure.client.Client(node, timeout=30)
        initial = client.get_configuration(timeout=30)
        initial = {k: v for k, v in initial.items() if k in set(BOOL_PARAMS) | set(NUMERIC_PARAMS)}
        queue_size = rospy.get_param(node + '/queue_size', 5)
        if not wait_until(lambda: self.mon.diag is not None, 30.0):
            raise RuntimeError('no processing diagnostics from %s' % node)

        self.set_subscribers(list(OUTPUTS))
        threads = [threading.Thread(target=f, args=x, daemon=True) for f, x in
                   ((self.subscriber_churn, ()), (self.parameter_churn, (client, initial)), (self.rss_sampler, ()))]
        for t in threads:
            t.start()
        wait_until(lambda: pub_c.get_num_connections() > 0, 10.0)

        # RSS: churn for `warmup` frames, then a reference window (start configuration, every
        # output subscribed, no churn) of `ref` frames; the same window ends the run. Growth =
        # median RSS of the second half of the last window - that of the first window.
        warmup = max(100, a.frames // 10)
        ref = max(90, min(300, a.frames // 20))
        windows = [(warmup, warmup + ref), (a.frames - ref, a.frames)]
        sent_connected = 0          # colour frames rospy sent to the nodelet (its header.seq)
        connected = False
        cycles = 0                  # input subscribe periods seen by the publisher
        bad_sent = {k: 0 for k in BAD_KINDS}
        bad_connected = {k: 0 for k in BAD_KINDS}
        published_connected = 0
        period = 1.0 / a.rate
        next_t = time.time()
        late = 0
        last_stamp = rospy.Time(0)
        t_pub0 = time.time()
        for i in range(a.frames):
            if rospy.is_shutdown() or not self.alive:
                break
            now = time.time()
            if next_t > now:
                time.sleep(next_t - now)
            elif now - next_t > period:
                late += 1
                next_t = now  # behind: keep the rate from here, no burst
            next_t += period
            for w in windows:
                if i == w[0]:
                    self.reference_state(client, initial)
                elif i == w[1]:
                    self.paused.clear()
            kind = None
            if i >= 10 and not self.paused.is_set() and self.rng.random() < a.bad_fraction:
                kind = BAD_KINDS[sum(bad_sent.values()) % len(BAD_KINDS)]  # each kind in turn
            colour, depth, info = bad[kind] if kind else frames[i % len(frames)]
            stamp = rospy.Time.now()
            if stamp <= last_stamp:
                stamp = last_stamp + rospy.Duration(0, 1000)
            last_stamp = stamp
            for m in (colour, depth, info):
                if m is not None:
                    m.header.stamp = stamp
            n = pub_c.get_num_connections()
            if (n > 0) != connected:
                connected = n > 0
                cycles += connected
            if info is not None:
                pub_i.publish(info)
            pub_d.publish(depth)
            seq0 = pub_c.impl.seq
            pub_c.publish(colour)
            sent = pub_c.impl.seq - seq0
            sent_connected += sent
            published_connected += n > 0
            self.published = i + 1
            if kind:
                bad_sent[kind] += 1
                bad_connected[kind] += sent
            if (i + 1) % 1000 == 0:
                d = self.mon.diag or {}
                log('%d frames, %.1f Hz, received %s processed %s, RSS %s kB, %d param / %d subscriber changes' % (
                    i + 1, (i + 1) / (time.time() - t_pub0), d.get('Frames received'), d.get('Frames processed'),
                    self.rss[-1][2] if self.rss else '?', self.param_changes, self.sub_changes))
        t_pub1 = time.time()

        # settle: churn stops, start configuration back, every output subscribed, then the final
        # counters: two consecutive reports with the same received/waiting counts
        self.stop.set()
        for t in threads:
            t.join(timeout=30)
        try:
            client.update_configuration(initial)
        except Exception as e:  # noqa: BLE001
            log('restoring the configuration failed: %s' % e)
        self.stop.clear()
        rss_thread = threading.Thread(target=self.rss_sampler, daemon=True)
        rss_thread.start()
        seen = []  # (report number, received) of each new report

        def settled():
            with self.mon.lock:
                n, d = self.mon.reports, self.mon.diag
            if d and (not seen or seen[-1][0] != n):
                seen.append((n, counter(d, 'Frames received')))
            return len(seen) >= 3 and len(set(r for _, r in seen[-3:])) == 1
        if not wait_until(settled, 15.0, period=0.1):
            log('the counters did not settle within 15 s')
        self.stop.set()
        rss_thread.join(timeout=5)
        with self.mon.lock:
            final = dict(self.mon.diag) if self.mon.diag else {}
            diag_age = time.time() - self.mon.diag_time if self.mon.diag_time else None
        self.set_subscribers([])
        alive = self.alive and rss_kb(self.pid) is not None and self._lookup(node) is not None
        # the nodelet leaves the manager before the launch shuts down (which keeps the manager's
        # exit clear of nodelet_core's bond use-after-free, docs/RELIABILITY.md): unloaded, gone
        # from the manager's list, the manager alive
        unloaded = alive and unload_nodelet(manager, node) and rss_kb(self.pid) is not None

        # --- checks ---------------------------------------------------------------------------
        received = counter(final, 'Frames received')
        lost = counter(final, 'Frames lost before the nodelet')
        edge = sent_connected - received - lost
        edge_bound = cycles * (queue_size + int(math.ceil(a.rate * 0.5)))
        ok_final, final_text = accounting_holds(final) if final else (False, 'no diagnostics')
        accounting_ok = (ok_final and self.mon.violations == 0 and self.mon.reports > 0 and 0 <= edge <= edge_bound)
        rss = list(self.rss)
        rss_start = rss[0][2] if rss else None
        rss_end = rss[-1][2] if rss else None
        rss_max = max((r[2] for r in rss if r[1] >= warmup), default=None)

        def window_rss(w):
            vals = sorted(r[2] for r in rss if w[0] + (w[1] - w[0]) // 2 <= r[1] < w[1] and r[0] <= t_pub1)
            vals = vals or sorted(r[2] for r in rss if w[0] <= r[1] <= w[1])  # short runs
            return vals[len(vals) // 2] if vals else None
        rss_warm, rss_last = window_rss(windows[0]), window_rss(windows[1])
        growth_kb = (rss_last - rss_warm) if (rss_last is not None and rss_warm is not None) else None
        rss_ok = growth_kb is not None and growth_kb < a.rss_limit_mb * 1024
        nan_total = sum(self.mon.nan.values())
        checks = {
            'no_crash': alive and diag_age is not None and diag_age < 10.0,
            'every_frame_accounted': accounting_ok,
            'rss_growth_below_limit': rss_ok,
            'no_nan_in_outputs': nan_total == 0 and sum(self.mon.messages.values()) > 0,
            'unloads_from_the_manager': unloaded,
        }
        report = {
            'pass': all(checks.values()),
            'checks': checks,
            'command': ' '.join(sys.argv),
            'bag': a.bag,
            'image_size': [frames[0][0].width, frames[0][0].height],
            'bag_frames': len(frames),
            'frames_requested': a.frames,
            'frames_published': self.published,
            'rate_hz_target': a.rate,
            'rate_hz_actual': round(self.published / max(t_pub1 - t_pub0, 1e-9), 2),
            'late_frames': late,
            'duration_s': round(time.time() - t_start, 1),
            'publish_duration_s': round(t_pub1 - t_pub0, 1),
            'bad_frames_published': bad_sent,
            'bad_frames_sent_to_nodelet': bad_connected,
            'parameter_changes': self.param_changes,
            'parameter_resets': self.param_resets,
            'parameter_errors': self.param_errors,
            'subscriber_changes': self.sub_changes,
            'periods_without_subscribers': self.none_periods,
            'input_subscribe_periods': cycles,
            'accounting': {
                'frames_published_while_subscribed': published_connected,
                'frames_sent_to_nodelet': sent_connected,
                'received': received,
                'lost_before_nodelet': lost,
                'edge_frames': edge,
                'edge_bound': edge_bound,
                'synchronised': counter(final, 'Frames synchronised'),
                'processed': counter(final, 'Frames processed'),
                'dropped': counter(final, 'Frames dropped'),
                'dropped_by_reason': drop_reasons(final),
                'skipped_no_subscriber': counter(final, 'Frames skipped (no subscriber)'),
                'not_synchronised': counter(final, 'Frames not synchronised'),
                'waiting': counter(final, 'Frames waiting'),
                'unaccounted': counter(final, 'Frames unaccounted'),
                'pending_ring_overflows': counter(final, 'Pending ring overflows'),
                'synchronised_late': counter(final, 'Frames synchronised late'),
                'final_rule': final_text,
                'diagnostics_reports_checked': self.mon.reports,
                'reports_violating_rule': self.mon.violations,
                'violation_examples': self.mon.violation_examples,
            },
            'rss_kb': {'start': rss_start, 'after_warmup': rss_warm, 'warmup_frames': warmup,
                       'reference_windows': windows, 'max_after_warmup': rss_max, 'last_window': rss_last,
                       'end': rss_end, 'growth_after_warmup': growth_kb, 'limit': a.rss_limit_mb * 1024,
                       'samples': [[round(t - t_pub0, 1), n, kb] for t, n, kb in rss]},
            'outputs_received': self.mon.messages,
            'non_finite_values': self.mon.nan,
            'non_finite_examples': self.mon.nan_examples,
        }
        self.write_report(report)
        return report

    def _lookup(self, name):
        try:
            return rosgraph.Master('/soak').lookupNode(name)
        except Exception:  # noqa: BLE001 - not (yet) registered
            return None

    def write_report(self, r):
        os.makedirs(self.a.report_dir, exist_ok=True)
        with open(os.path.join(self.a.report_dir, 'soak_report.json'), 'w') as f:
            json.dump(r, f, indent=2, sort_keys=True)
        acc, rss = r['accounting'], r['rss_kb']
        mb = (lambda kb: '%.1f MB' % (kb / 1024.0) if kb is not None else '?')
        lines = [
            '# Soak report', '',
            '`%s`' % r['command'], '',
            '| check | result |', '| --- | --- |',
        ] + ['| %s | %s |' % (k, 'PASS' if v else 'FAIL') for k, v in r['checks'].items()] + [
            '', '- frames published: %d (%dx%d, bag of %d frames looped) at %.1f Hz (target %.0f), %.0f s; '
            'bad frames: %s' % (r['frames_published'], r['image_size'][0], r['image_size'][1], r['bag_frames'],
                                r['rate_hz_actual'], r['rate_hz_target'], r['publish_duration_s'],
                                ', '.join('%s %d' % kv for kv in r['bad_frames_published'].items())),
            '- parameter changes: %d (%d resets to the start configuration, %d errors); subscriber changes: %d '
            '(%d periods without any), %d input subscribe periods' % (
                r['parameter_changes'], r['parameter_resets'], r['parameter_errors'], r['subscriber_changes'],
                r['periods_without_subscribers'], r['input_subscribe_periods']),
            '- nodelet: received %d = processed %d + dropped %d + skipped %d + not synchronised %d + waiting %d '
            '(%d reports checked, %d violating)' % (
                acc['received'], acc['processed'], acc['dropped'], acc['skipped_no_subscriber'],
                acc['not_synchronised'], acc['waiting'], acc['diagnostics_reports_checked'],
                acc['reports_violating_rule']),
            '- dropped by reason: %s' % ('; '.join('%s: %d' % kv for kv in sorted(acc['dropped_by_reason'].items()))
                                         or 'none'),
            '- sent to the nodelet %d = received %d + lost before it %d + edge %d (bound %d)' % (
                acc['frames_sent_to_nodelet'], acc['received'], acc['lost_before_nodelet'], acc['edge_frames'],
                acc['edge_bound']),
            '- manager RSS: start %s; reference window after warm-up (frames %d-%d) %s, last reference window '
            '(frames %d-%d) %s: growth %s (limit %s); max after warm-up %s, end %s' % (
                mb(rss['start']), rss['reference_windows'][0][0], rss['reference_windows'][0][1],
                mb(rss['after_warmup']), rss['reference_windows'][1][0], rss['reference_windows'][1][1],
                mb(rss['last_window']), mb(rss['growth_after_warmup']), mb(rss['limit']),
                mb(rss['max_after_warmup']), mb(rss['end'])),
            '- output messages checked: %d; non-finite values: %d' % (
                sum(r['outputs_received'].values()), sum(r['non_finite_values'].values())),
            '', 'Overall: **%s**' % ('PASS' if r['pass'] else 'FAIL'), '']
        with open(os.path.join(self.a.report_dir, 'soak_report.md'), 'w') as f:
            f.write('\n'.join(lines))


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    p.add_argument('--bag', help='rosbag with <ns>/rgb/image_rect_color, depth_registered/image_rect, rgb/camera_info')
    p.add_argument('--generate-frames', type=int, default=0,
                   help='no --bag: generate a synthetic bag of this many frames (temporary directory)')
    p.add_argument('--width', type=int, default=640)
    p.add_argument('--height', type=int, default=380)
    p.add_argument('--frames', type=int, default=int(os.environ.get('SOAK_FRAMES', 10000)))
    p.add_argument('--rate', type=float, default=30.0, help='Hz')
    p.add_argument('--ns', default='/camera')
    p.add_argument('--node', default='lane_detector')
    p.add_argument('--manager', default='manager')
    p.add_argument('--param-period', type=float, default=3.0, help='mean s between parameter changes')
    p.add_argument('--sub-period', type=float, default=4.0, help='mean s between subscriber changes')
    p.add_argument('--bad-fraction', type=float, default=0.01, help='share of injected bad frames')
    p.add_argument('--rss-limit-mb', type=float, default=5.0)
    p.add_argument('--seed', type=int, default=1)
    p.add_argument('--report-dir', default='build/soak')
    args, _ = p.parse_known_args(argv)  # rostest adds --gtest_output, roslaunch __name:=...
    return args


def main():
    argv = rospy.myargv(sys.argv)[1:]
    rostest_mode = any(x.startswith('--gtest_output') for x in sys.argv)
    args = parse_args(argv)
    rospy.init_node('soak', anonymous=True)
    tmp = None
    if not args.bag:
        tmp = tempfile.mkdtemp(prefix='soak_')
        args.bag = generate_bag(args.generate_frames or 20, args.width, args.height, tmp)
    if rostest_mode:
        import unittest
        import rostest

        class SoakShort(unittest.TestCase):
            def test_soak(self):
                report = Soak(args).run()
                print(open(os.path.join(args.report_dir, 'soak_report.md')).read())
                self.assertTrue(report['pass'], json.dumps(report['checks']))

        rostest.rosrun('rgbd_lane_detector', 'soak_short', SoakShort, sys.argv)
        return 0
    report = Soak(args).run()
    print(open(os.path.join(args.report_dir, 'soak_report.md')).read(), flush=True)
    for k, v in report['checks'].items():
        print('%s: %s' % ('PASS' if v else 'FAIL', k))
    print('SOAK %s' % ('PASS' if report['pass'] else 'FAIL'), flush=True)
    return 0 if report['pass'] else 1


if __name__ == '__main__':
    sys.exit(main())
