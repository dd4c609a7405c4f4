# Used by catkin_python_setup(); do not run directly.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(
    packages=['pepper_interface_tests',
              'pepper_interface_tests.sensors',
              'pepper_interface_tests.audio_bridge',
              'pepper_interface_tests.emulator',
              'pepper_interface_tests.report',
              'pepper_interface_tests.report.views'],
    package_dir={'': 'src'},
    package_data={'pepper_interface_tests.report': ['templates/*']},
))
