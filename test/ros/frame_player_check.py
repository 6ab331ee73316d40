#!/usr/bin/env python3
"""frame_player.test (issue 23): FramePlayerNodelet and LaneDetectorNodelet in one manager, the
player in lockstep (the next frame only once the previous frame's lane_plane came back), so no
timing is assumed: every published frame must come back, each once, and the nodelet's own frame
accounting must show every frame received and processed, none lost before it, none unsynchronised.
Waits on conditions (the player's latched summary, a diagnostics report with every frame
processed) with generous time limits, never on fixed sleeps."""
import sys
import threading
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus


class FramePlayerTest(unittest.TestCase):
    def setUp(self):
        self.cond = threading.Condition()
        self.summary = None
        self.report = None
        self.count = rospy.get_param("~count")
        rospy.Subscriber("frame_player/summary", DiagnosticStatus, self.on_summary, queue_size=1)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag, queue_size=20)

    def on_summary(self, msg):
        with self.cond:
            self.summary = {kv.key: kv.value for kv in msg.values}
            self.cond.notify_all()

    def on_diag(self, msg):
        for st in msg.status:
            if "lane_detector" in st.name and st.name.endswith("processing"):
                with self.cond:
                    self.report = {kv.key: kv.value for kv in st.values}
                    self.cond.notify_all()

    def wait_for(self, pred, timeout):
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        with self.cond:
            while not pred() and not rospy.is_shutdown() and rospy.Time.now() < deadline:
                self.cond.wait(0.5)
            return pred()

    def test_every_frame_comes_back(self):
        self.assertTrue(self.wait_for(lambda: self.summary is not None, 300.0),
                        "no summary from the frame player")
        s = self.summary
        n = self.count
        self.assertEqual(int(s["published"]), n, s)
        self.assertEqual(int(s["outputs"]), n, s)
        self.assertEqual(int(s["lost"]), 0, s)
        self.assertEqual(int(s["duplicates"]), 0, s)
        self.assertEqual(int(s["unknown"]), 0, s)
        self.assertEqual(int(s["warmup_published"]), 0, s)
        self.assertEqual(s["size"], "640x480")
        mean, p50, p99, mx = (float(s[k]) for k in ("latency_mean_ms", "latency_p50_ms",
                                                    "latency_p99_ms", "latency_max_ms"))
        self.assertGreater(mean, 0.0)
        self.assertTrue(0.0 < p50 <= p99 <= mx, s)
        # the nodelet's own accounting: a report once every frame is processed
        processed = lambda: (self.report is not None  # noqa: E731
                             and int(self.report.get("Frames processed", "0")) >= n)
        self.assertTrue(self.wait_for(processed, 60.0), self.report)
        r = self.report
        self.assertEqual(int(r["Frames received"]), n, r)
        self.assertEqual(int(r["Frames processed"]), n, r)
        self.assertEqual(int(r["Frames dropped"]), 0, r)
        self.assertEqual(int(r["Frames not synchronised"]), 0, r)
        self.assertEqual(int(r["Frames lost before the nodelet"]), 0, r)
        self.assertEqual(int(r["Frames unaccounted"]), 0, r)


if __name__ == "__main__":
    rospy.init_node("frame_player_check")
    rostest.rosrun("rgbd_lane_detector", "frame_player_check", FramePlayerTest, sys.argv)
