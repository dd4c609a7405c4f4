"""Odometry: x and y over time, and the path."""
from .. import plots
from ..blocks import Heading, Image


def render(r, v, ctx):
    if not v.x:
        return []
    return [Heading('Position over time'), Image(plots.odometry(v.x, v.y), 'odometry position over time')]
