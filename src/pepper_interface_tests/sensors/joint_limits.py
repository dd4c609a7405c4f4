"""Pepper's joint limits, from the robot description (data, no logic).

Source: ros-naoqi/pepper_robot, pepper_description/urdf/pepper1.0_generated_urdf/pepper.urdf
(commit 60d4e08d9d46e7ac1f86b85dff6e0009d043fd1c), each joint's `<limit lower upper velocity>`;
the last number of each row is the line of that `<limit>` element. The wheels are continuous
joints (no position limit; their positions wrap at +-pi). The simulator's joints are the same
(awesomebytes/pepper_robot builds its Gazebo model from the same generated URDF).

name -> (lower rad, upper rad, velocity rad/s, pepper.urdf line)
"""

URDF = 'ros-naoqi/pepper_robot pepper_description/urdf/pepper1.0_generated_urdf/pepper.urdf'

LIMITS = {
    'HeadYaw':        (-2.08567, 2.08567, 7.33998, 15),
    'HeadPitch':      (-0.706858, 0.637045, 9.22756, 41),
    'HipRoll':        (-0.514872, 0.514872, 2.27032, 67),
    'HipPitch':       (-1.03847, 1.03847, 2.93276, 93),
    'KneePitch':      (-0.514872, 0.514872, 2.93276, 119),
    'LShoulderPitch': (-2.08567, 2.08567, 7.33998, 177),
    'LShoulderRoll':  (0.00872665, 1.56207, 9.22756, 203),
    'LElbowYaw':      (-2.08567, 2.08567, 7.33998, 229),
    'LElbowRoll':     (-1.56207, -0.00872665, 9.22756, 255),
    'LWristYaw':      (-1.82387, 1.82387, 17.3835, 281),
    'LHand':          (0.02, 0.98, 12.56, 307),
    'RShoulderPitch': (-2.08567, 2.08567, 7.33998, 320),
    'RShoulderRoll':  (-1.56207, -0.00872665, 9.22756, 346),
    'RElbowYaw':      (-2.08567, 2.08567, 7.33998, 372),
    'RElbowRoll':     (0.00872665, 1.56207, 9.22756, 398),
    'RWristYaw':      (-1.82387, 1.82387, 17.3835, 424),
    'RHand':          (0.02, 0.98, 12.56, 450),
    'WheelFL':        (None, None, 6.28319, 1403),    # continuous
    'WheelB':         (None, None, 6.28319, 1429),    # continuous
    'WheelFR':        (None, None, 6.28319, 1455),    # continuous
}
