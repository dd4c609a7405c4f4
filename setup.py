# Used by catkin_python_setup(); do not run directly.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(
    packages=['pepper_interface_tests',
              'pepper_interface_tests.plan',
              'pepper_interface_tests.sources',
              'pepper_interface_tests.media',
              'pepper_interface_tests.sensors',
              'pepper_interface_tests.outputs',
              'pepper_interface_tests.launch',
              'pepper_interface_tests.audio_bridge',
              'pepper_interface_tests.emulator',
              'pepper_interface_tests.outputs.report',
              'pepper_interface_tests.outputs.report.views'],
    package_dir={'': 'src'},
    package_data={'pepper_interface_tests.outputs.report': ['templates/*']},
    # Ubuntu 20.04's Python (ROS Noetic); the capture side alone also runs on NAOqi's 2.7
    python_requires='>=3.8',
))
