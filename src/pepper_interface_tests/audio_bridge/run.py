"""naoqiAudioPublisher's entry point: publisher.py on ROS 1, publisher2.py on ROS 2 (ROS_VERSION=2)."""
from typing import Optional, Sequence

from ..sources.live2 import ros_version


def main(argv: Optional[Sequence[str]] = None) -> int:
    if ros_version() == 2:
        from .publisher2 import main2
        return main2(argv)
    from .publisher import main as main1
    return main1(argv)
