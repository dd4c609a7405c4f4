"""The message classes the sources decode with (sources/messages.py)."""
from pepper_interface_tests.plan import catalog
from pepper_interface_tests.sources.messages import message_class


def test_audio_message_types_of_both_packages():
    assert message_class('naoqi_driver/AudioCustomMsg').__module__.startswith('pepper_interface_tests')
    mic = catalog.SENSORS['microphone']
    assert catalog.accepts_type(mic, 'naoqi_driver/AudioCustomMsg')
    assert catalog.accepts_type(mic, 'pepper_interface_tests/AudioCustomMsg')
    assert not catalog.accepts_type(mic, 'std_msgs/String')
    assert not catalog.accepts_type(catalog.SENSORS['laser'], 'sensor_msgs/Range')
