"""Runs test/nodes/sensor_test_core.test through `rostest` (which starts its own master on a random
port), as `catkin_make run_tests` / add_rostest would, and checks that it passes and that the
sensorTest node really ran with the launch file's private params."""
import json
import os
import subprocess
import xml.etree.ElementTree as ET

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
PKG_DIR = os.path.dirname(HERE)
NODES = os.path.join(HERE, 'nodes')   # the rostest files and their nodes
TEST_FILE = os.path.join(NODES, 'sensor_test_core.test')


def test_nodes_of_the_test_file_are_executable():
    """roslaunch only starts executable files (rosrun finds them anywhere in the package)."""
    for name in ('core_publisher.py', 'rostest_sensor_test.py'):
        assert os.access(os.path.join(NODES, name), os.X_OK), name
    assert os.access(os.path.join(PKG_DIR, 'scripts', 'sensorTest'), os.X_OK)


@pytest.mark.timeout(240)
def test_rostest_sensor_test_core(tmp_path):
    out = tmp_path / 'out'
    results = tmp_path / 'test_results'
    env = dict(os.environ)
    env['ROS_HOME'] = str(tmp_path / 'ros_home')       # logs of this launch stay here
    # as a user types it: rostest finds the file in the package
    cmd = ['rostest', '--results-base-dir', str(results), 'pepper_interface_tests',
           os.path.basename(TEST_FILE), 'output_dir:=%s' % out]
    p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       timeout=200, start_new_session=True)
    assert p.returncode == 0, p.stdout[-6000:]
    assert '* RESULT: SUCCESS' in p.stdout
    # the test node's own results: every test method ran and passed
    node_xml = [f for f in os.listdir(str(results / 'pepper_interface_tests')) if f.startswith('rosunit-')]
    assert node_xml == ['rosunit-sensor_test_verdicts.xml']
    suite = ET.parse(str(results / 'pepper_interface_tests' / node_xml[0])).getroot()
    assert int(suite.get('tests')) == 5
    assert (suite.get('errors'), suite.get('failures')) == ('0', '0')
    # and sensorTest ran as a node with the params of the launch file
    with open(str(out / 'sensorTestResults.json')) as f:
        data = json.load(f)
    assert [s['name'] for s in data['sensors']] == ['backSonar', 'frontSonar', 'laser', 'odometry', 'speech']
    assert data['options'].get('duration') == 2.0 and data['options'].get('cameras') == 'pepper'
    assert [s['verdict'] for s in data['sensors']] == ['PASS', 'FAIL', 'PASS', 'PASS', 'PASS']
