"""The emulator's `network` condition (emulator/network.py): holds of HOLD s every HOLD_EVERY s,
what wants to cross during one waits until it ends, nothing waits outside them."""
from pepper_interface_tests.emulator.network import HOLD, HOLD_EVERY, Network, network_of


def test_holds_last_and_recur_within_their_documented_bounds():
    net = Network(seed=3, start=0.0)
    t, holds, inside = 0.0, [], None
    while t < 120.0:                         # the network sampled every 10 ms for two minutes
        w = net.wait(t)
        if w > 0 and inside is None:
            inside = (t, t + w)              # a hold began; it ends when the wait says
        elif w == 0 and inside is not None:
            holds.append(inside)
            inside = None
        t = round(t + 0.01, 2)
    assert len(holds) >= 120.0 / (HOLD_EVERY[1] + HOLD[1]) - 1
    for begin, end in holds:
        assert HOLD[0] - 0.011 <= end - begin <= HOLD[1]
    for (_, end), (begin, _) in zip(holds, holds[1:]):
        assert HOLD_EVERY[0] - 0.011 <= begin - end <= HOLD_EVERY[1] + 0.011


def test_within_a_hold_everything_waits_for_its_end():
    net = Network(seed=1, start=0.0)
    t = 0.0
    while net.wait(t) == 0:
        t += 0.005
    end = t + net.wait(t)
    assert abs((t + 0.1) + net.wait(t + 0.1) - end) < 1e-9   # later in the hold: the same end
    assert net.wait(end) == 0.0


def test_none_is_no_network():
    assert network_of('none') is None and isinstance(network_of('wifi'), Network)
