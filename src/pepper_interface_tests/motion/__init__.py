"""The motion check's home (--move): its plan's steps, its commands, its witnesses, its safety
and its rules, between media/ and sensors/ in the stages (sensors/motion.py, the `motion`
family's Check, drives it; nothing here imports a check).

- commands.py  the three topics naoqi_driver takes (registerDefaultSubscriber,
               src/naoqi_driver.cpp:933-938): /move_base_simple/goal (a bounded, relative
               moveTo), /joint_angles (setAngles at a speed fraction), /cmd_vel (used only to
               stop: a zero twist); nothing is sent once closed.
- witnesses.py the sensors that watch the motion (joint states, odometry, IMU, laser, sonars,
               head cameras, bumpers, /diagnostics), subscribed whether or not they are selected,
               recorded into a record.Recording.
- record.py    what the witnesses saw: time series, under one lock (pure data).
- estimate.py  yaw from a quaternion, the integrated gyro, a scan's turn, a picture's shift.
- safety.py    before moving (free space, bumpers, health, stiffness) and while moving (a
               bumper, an obstacle closer than stop_distance).
- sequence.py  the steps (head +a, -a, back; base +t, back), each waited for, and the stop.
- rules.py     the judging: each finding on the row of the sensor it concerns, the vote of the
               base's witnesses, the motion row's own verdict.
"""
