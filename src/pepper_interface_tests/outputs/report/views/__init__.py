"""One small renderer per sensor family.

`render(family, result, values, ctx)` returns the family's blocks (blocks.py) for the sensor's
section: a view receives the SensorResult (for its name and artifacts) and the family's typed
values (values.py); `ctx` (page.View) gives the run's files (files.RunFiles) and the anchors of
other sections. A family without a view shows only the common parts of its section.
"""

from . import audio, camera, depth, imu, joints, laser, odometry, speech
from . import range as range_view

VIEWS = {'range': range_view, 'laser': laser, 'camera': camera, 'depth': depth, 'audio': audio,
         'joints': joints, 'odometry': odometry, 'imu': imu, 'speech': speech}

def render(family, result, values, ctx):
    view = VIEWS.get(family)
    if view is None or values is None:
        return []
    return view.render(result, values, ctx)
