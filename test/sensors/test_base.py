"""The checks' shared value helpers (sensors/base.py, sensors/values)."""
from pepper_interface_tests.sensors.base import Acc, Tally, fmt


def test_value_helpers():
    a = Acc()
    for v in (1.0, 2.0, float('nan'), 6.0, float('inf')):
        a.add(v)
    assert a.as_dict() == {'min': 1.0, 'mean': 3.0, 'max': 6.0} and a.nonfinite == 2
    assert a.text('m') == 'min 1, mean 3, max 6 m'
    assert Acc().text() == 'no finite values'
    assert fmt(0.5236) == '0.5236' and fmt(2.0) == '2' and fmt(float('nan')) == 'nan'
    assert fmt([1.0, 0.25]) == '[1, 0.25]' and fmt(0.0) == '0'
    t = Tally()
    t.add('k', 'range bad', 4.0)
    t.add('k', 'range bad', 9.0)
    assert t.reasons(10) == ['range bad in 2 of 10 messages (e.g. 4)']
