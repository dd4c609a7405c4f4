#!/usr/bin/env python3
"""rostest node for sensor_test_core.test: waits until the sensorTest node has written its
results into ~output_dir, then checks every verdict, the order and the three output files."""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rostest_results import wait_for_results  # noqa: E402

PKG = 'pepper_interface_tests'
NAMES = ['backSonar', 'frontSonar', 'laser', 'odometry', 'speech']


class SensorTestVerdicts(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('sensor_test_verdicts')
        cls.out = rospy.get_param('~output_dir')
        cls.missing, found = wait_for_results(cls.out, float(rospy.get_param('~timeout', 100)))
        if found:
            cls.data, cls.dat, cls.junit, cls.sensors = (found['json'], found['dat'], found['junit'],
                                                         found['sensors'])

    def setUp(self):
        self.assertEqual(self.missing, [], 'sensorTest did not write its results')

    def test_params_chose_sensors_and_order(self):
        self.assertEqual([s['name'] for s in self.data['sensors']], NAMES)
        self.assertEqual(self.data['mode'], 'sequential')
        for name in NAMES[:-1]:
            self.assertLess(self.sensors[name]['window_s'], 4.0, name)   # ~duration 2 s
        for a, b in zip(NAMES, NAMES[1:]):
            self.assertGreaterEqual(self.sensors[b]['started_at'], self.sensors[a]['ended_at'] - 0.01)

    def test_good_sensors_pass(self):
        for name in ('backSonar', 'laser', 'odometry'):
            s = self.sensors[name]
            self.assertEqual(s['verdict'], 'PASS', '%s: %s' % (name, s['reasons']))
            self.assertGreater(s['messages'], 5)

    def test_faulty_sonar_fails_with_its_reason(self):
        s = self.sensors['frontSonar']
        self.assertEqual(s['verdict'], 'FAIL')
        self.assertTrue(any("range outside the sensor's physical limits [0, 5] m" in r for r in s['reasons']),
                        s['reasons'])
        self.assertEqual(self.data['exit_code'], 1)

    def test_speech_delivered_to_the_listener(self):
        s = self.sensors['speech']
        self.assertEqual(s['verdict'], 'PASS', s['reasons'])
        self.assertTrue(any('speech_listener' in n for n in s['values']['subscribers']), s['values'])

    def test_output_files(self):
        run = self.dat.split('[TESTING] ############ SENSORS ############')[-1]
        for title in ('BACK SONAR', 'FRONT SONAR', 'LASER', 'ODOMETRY', 'SPEECH'):
            self.assertIn('[TESTING] ---- %s ----' % title, run)
        self.assertIn('[RESULT] FAIL: range outside', run)
        self.assertIn('[END TIME] ', run)
        cases = self.junit.findall('testcase')
        self.assertEqual([c.get('name') for c in cases], NAMES)
        failed = [c.get('name') for c in cases if c.find('failure') is not None]
        self.assertEqual(failed, ['frontSonar'])


if __name__ == '__main__':
    rostest.rosrun(PKG, 'sensor_test_verdicts', SensorTestVerdicts, sys.argv)
