"""Laser: polar plot of the last scan, blind and invalid beams marked at the edge."""
from .. import plots
from ..blocks import Heading, Image


def render(r, scan, ctx):
    return [Heading('Last scan'), Image(plots.laser_scan(scan), 'polar plot of the last laser scan')]
