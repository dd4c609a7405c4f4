"""A real driver's /tf against the emulator's tree (emulator/urdf_tree.py driver_tree), message
by message, for the ROS 1 and ROS 2 golden recordings alike (test_golden_recordings.py,
test_conformance2.py): each /tf message is paired with the joint state of its stamp; the same 84
parent-child pairs (odom -> base_link aside), every transform the same to 1e-5 m and 1e-5 in each
quaternion component (q and -q: the same rotation)."""
from typing import Callable, Dict, Hashable, Iterable, Set, Tuple

from pepper_interface_tests.emulator.urdf_tree import driver_tree


def compare_trees(trees: Iterable, states: Dict[Hashable, Dict[str, float]],
                  stamp_of: Callable[[object], Hashable]) -> Tuple[int, Set[float]]:
    """Compare every /tf message whose stamp has a joint state; returns how many were compared
    and the head yaws they were compared at (rounded to 0.1 rad)."""
    compared, head_yaws = 0, set()
    for m in trees:
        stamps = {stamp_of(x) for x in m.transforms if x.header.frame_id != 'odom'}
        assert len(stamps) == 1, stamps                      # one stamp: the joint state's
        positions = states.get(stamps.pop())
        if positions is None:
            continue
        real = {(x.header.frame_id, x.child_frame_id): x.transform for x in m.transforms}
        assert len(real) == 84 and ('odom', 'base_link') in real, len(real)
        emulated = {(p, c): (xyz, q) for p, c, xyz, q in driver_tree(positions)}
        assert set(emulated) == set(real) - {('odom', 'base_link')}
        for pair, (xyz, q) in emulated.items():
            t = real[pair]
            got = (t.translation.x, t.translation.y, t.translation.z)
            assert max(abs(a - b) for a, b in zip(got, xyz)) < 1e-5, (pair, got, xyz)
            r = (t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w)
            same = max(abs(a - b) for a, b in zip(r, q))
            flipped = max(abs(a + b) for a, b in zip(r, q))       # q and -q: the same rotation
            assert min(same, flipped) < 1e-5, (pair, r, q)
        head_yaws.add(round(positions['HeadYaw'], 1))
        compared += 1
    return compared, head_yaws
