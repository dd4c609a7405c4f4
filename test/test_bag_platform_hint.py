"""A bag checked with the wrong platform: every sensor fails as "not in the bag", and a note
names the platform whose topics the bag does hold. Real bags written with rosbag, the real
sensorTest script with no master."""
import genpy
import rosbag

from test_bag_source import T0, results, run_bag, sonar


def write(path, topics):
    with rosbag.Bag(str(path), 'w') as bag:
        for i in range(30):
            t = T0 + 0.1 * i
            for topic in topics:
                bag.write(topic, sonar(t), genpy.Time.from_sec(t))
    return path


def test_simulator_bag_checked_as_robot_suggests_the_simulator(tmp_path):
    bag = write(tmp_path / 'sim.bag', ['/pepper/sonar_back', '/pepper/sonar_front'])
    p = run_bag(bag, tmp_path / 'out', 'backSonar,frontSonar')
    assert p.returncode == 1 and 'Traceback' not in p.stderr, p.stdout + p.stderr
    r = results(tmp_path / 'out')
    assert r['backSonar']['reasons'] == ['topic /naoqi_driver/sonar/back is not in the bag']
    notes = [ln for ln in p.stdout.splitlines() if 'note:' in ln and '--platform' in ln]
    assert len(notes) == 1, p.stdout
    assert ('0 of the 2 robot topics are in the bag, but 2 of the simulator topics are '
            '(/pepper/sonar_back, /pepper/sonar_front): check it with --platform simulator') in notes[0]


def test_right_platform_or_unrelated_bag_gets_no_hint(tmp_path):
    own = write(tmp_path / 'robot.bag', ['/naoqi_driver/sonar/back'])
    p = run_bag(own, tmp_path / 'o1', 'backSonar,frontSonar')     # frontSonar merely missing
    assert '--platform' not in p.stdout, p.stdout
    other = write(tmp_path / 'other.bag', ['/some/other'])
    p = run_bag(other, tmp_path / 'o2', 'backSonar')
    assert p.returncode == 1 and '--platform' not in p.stdout, p.stdout
