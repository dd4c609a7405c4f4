"""Joint states (sensor_msgs/JointState): unique names, array lengths, finite positions,
the expected Pepper joints present."""
import math

from .base import Acc, Check, fmt


class JointsCheck(Check):
    family = 'joints'

    def __init__(self, plan, ctx):
        super().__init__(plan, ctx)
        self.joints = {}     # name -> {'position': Acc, 'velocity': Acc, 'effort': Acc}
        self.names_seen = []

    def fields(self, msg):
        out = [('Header frame id', msg.header.frame_id), ('Number of joints', len(msg.name))]
        for i, name in enumerate(msg.name):
            def at(seq):
                return fmt(seq[i]) if i < len(seq) else 'n/a'
            out.append(('Joint', '%s: Position %s, Velocity %s, Effort %s'
                        % (name, at(msg.position), at(msg.velocity), at(msg.effort))))
        return out

    def on_message(self, msg, t):
        names = list(msg.name)
        n = len(names)
        if len(set(names)) != n:
            dup = sorted({x for x in names if names.count(x) > 1})
            self.failures.add('dup', 'duplicate joint names %s' % ', '.join(dup))
        for label, seq in (('position', msg.position), ('velocity', msg.velocity), ('effort', msg.effort)):
            if len(seq) not in (0, n):
                self.failures.add('len_' + label, '%s has %d values for %d joints' % (label, len(seq), n))
        for i, name in enumerate(names):
            acc = self.joints.get(name)
            if acc is None:
                acc = self.joints[name] = {'position': Acc(), 'velocity': Acc(), 'effort': Acc()}
                self.names_seen.append(name)
            for label, seq in (('position', msg.position), ('velocity', msg.velocity), ('effort', msg.effort)):
                if len(seq) == n:
                    acc[label].add(seq[i])
            if len(msg.position) == n and math.isnan(msg.position[i]):
                self.failures.add('nan_' + name, 'position of %s is NaN' % name)

    def finish(self):
        self.values['joints'] = {name: {k: a.as_dict() for k, a in acc.items()}
                                 for name, acc in self.joints.items()}
        self.values['joint_count'] = len(self.joints)
        expected = self.expect.joints
        missing = [j for j in expected if j not in self.joints]
        if self.count and missing:
            self.fail('expected joints missing: ' + ', '.join(missing))
        if self.count:
            self.notes.append('%d joints: %s' % (len(self.names_seen), ', '.join(self.names_seen)))
            for name in self.names_seen:
                acc = self.joints[name]
                self.notes.append('%s position %s; velocity %s; effort %s'
                                  % (name, acc['position'].text('rad'), acc['velocity'].text('rad/s'),
                                     acc['effort'].text()))
