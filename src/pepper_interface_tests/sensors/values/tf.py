"""The tf family's values (the robot's transform tree): see sensors/tf.py for the rules."""
from dataclasses import dataclass, field
from typing import List, Optional


@dataclass(frozen=True)
class TfLink:
    child: str = ''
    parent: str = ''


@dataclass(frozen=True)
class TfValues:
    messages: int = 0                   # /tf and /tf_static messages over the run
    static_messages: int = 0
    pairs: int = 0                      # parent-child pairs (child frames) seen
    roots: List[str] = field(default_factory=list)
    loops: List[List[str]] = field(default_factory=list)
    publishers: List[str] = field(default_factory=list)     # nodes that published on /tf
    # child frames published by two nodes: "child (node, node)"
    second_publishers: List[str] = field(default_factory=list)
    max_ahead_s: Optional[float] = None     # the newest stamp's lead over arrival (future)
    max_behind_s: Optional[float] = None    # its lag behind arrival
    odom_compared: int = 0
    odom_worst: Optional[float] = None      # m (position + 0.3 m x yaw): odom vs odom -> base_link
    head_compared: int = 0
    head_worst_rad: Optional[float] = None  # HeadYaw vs torso -> Neck
    head_moved_rad: Optional[float] = None  # how far the head turned in the run
    # the tree as drawn by the report: child -> parent (most named)
    links: List[TfLink] = field(default_factory=list)
