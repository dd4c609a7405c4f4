#!/usr/bin/env python3
"""rostest node for bag_playback.test: every sensor's verdict (and reason) is the expected one.

~expect: "sensor=VERDICT[:text];..." — one entry per sensor of the run; with text, one of the
sensor's reasons must contain it.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rostest_results import wait_for_results  # noqa: E402


def parse_expect(text):
    out = {}
    for entry in filter(None, (e.strip() for e in text.split(';'))):
        name, _, rest = entry.partition('=')
        verdict, _, reason = rest.partition(':')
        out[name.strip()] = (verdict.strip(), reason.strip())
    return out


class BagVerdicts(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('bag_verdicts')
        cls.expect = parse_expect(rospy.get_param('~expect'))
        cls.missing, cls.found = wait_for_results(rospy.get_param('~output_dir'),
                                                  float(rospy.get_param('~timeout', 100)))

    def test_results_written(self):
        self.assertEqual(self.missing, [], 'sensorTest did not write its results')

    def test_every_sensor_as_expected(self):
        self.assertTrue(self.found, 'no results')
        sensors = self.found['sensors']
        self.assertEqual(sorted(sensors), sorted(self.expect))
        for name, (verdict, reason) in self.expect.items():
            got = sensors[name]
            self.assertEqual(got['verdict'], verdict, '%s: %s' % (name, got['reasons']))
            if reason:
                self.assertTrue(any(reason in r for r in got['reasons']),
                                '%s: no reason with "%s" in %s' % (name, reason, got['reasons']))
            if verdict == 'PASS':
                self.assertGreaterEqual(got['messages'], 5, name)


if __name__ == '__main__':
    rostest.rosrun('pepper_interface_tests', 'bag_verdicts', BagVerdicts, sys.argv)
