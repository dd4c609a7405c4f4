"""The genpy message classes the package builds messages with or decodes into, looked up once
through the ROS seam (rosapi.msg: rospy's classes on ROS 1, built from the definitions on ROS 2,
where `sensor_msgs.msg` is rclpy's)."""
from . import rosapi

DiagnosticArray = rosapi.msg('diagnostic_msgs/DiagnosticArray')
Quaternion = rosapi.msg('geometry_msgs/Quaternion')
Odometry = rosapi.msg('nav_msgs/Odometry')
Image = rosapi.msg('sensor_msgs/Image')
Imu = rosapi.msg('sensor_msgs/Imu')
JointState = rosapi.msg('sensor_msgs/JointState')
LaserScan = rosapi.msg('sensor_msgs/LaserScan')
Range = rosapi.msg('sensor_msgs/Range')
String = rosapi.msg('std_msgs/String')
Bumper = rosapi.msg('naoqi_bridge_msgs/Bumper')
