"""The robot's own health (robotHealth): naoqi_driver's statuses on /diagnostics.

What the driver publishes (ros-naoqi/naoqi_driver src/converters/diagnostics.cpp; the
CSSR4Africa fork is the same), as one DiagnosticArray on /diagnostics (src/naoqi_driver.cpp:652)
at 1 Hz (share/boot_config.json "diag"):
- one status per joint, `naoqi_driver_joints:<joint>`, with Temperature and Stiffness
  (:159-205): OK below 68 °C, WARN "Hot" from 68 °C, ERROR "Too hot" from 74 °C (:57-58, 177-191);
- `naoqi_driver_joints:Status`, the aggregate: the worst joint level, Highest Temperature and
  Hot Joints (:207-222);
- `naoqi_driver_battery:Status` with Percentage, Charging and Fully Charged (:224-275): OK when
  charging or fully charged or above 60 %, WARN "Battery discharging" above 30 %, ERROR
  "Battery almost empty" at 30 % or less (:238-262).
Other nodes publish on /diagnostics too (sensorTest itself: outputs/diagnostics.py): only the
statuses named naoqi_driver_joints:* and naoqi_driver_battery:Status are judged, so this node's
own statuses never feed this check (a live window also never receives them, and the master
look-ups never count this node as a publisher of /diagnostics: sources/live.py).

The rules: PASS when the driver's statuses are OK. A joint at the driver's WARN ("Hot") and a
battery at WARN (discharging, 60 % or less) are warnings naming the joints and temperatures or
the charge; a joint at ERROR ("Too hot") and a battery at ERROR (almost empty) fail, saying what
to do. No driver status within --wait fails: the driver's diagnostics are off
(converters.diag.enabled in its boot_config.json) or the driver is not running. The worst level
seen in the window counts; the battery's charge and the hottest joints are in every output.

On a busy PC (issue 41): listening live, while nothing of the driver's has come and this PC is
busy (sensors/lag.py `pc_busy`: the load average above the cores, sensorTest's callbacks on a
CPU less than half of their time, or sensorTest itself not running for a second or more of the
window), the window waits BUSY_EXTRA s more; if still nothing at all reached it and the topic
has a publisher other than sensorTest (on ROS 1 the live source leaves out the connection rospy
makes to this node's own /diagnostics publisher: sources/live.py), the row is NOT JUDGED naming
the load and sensorTest's lag, not a FAIL of the robot: the arrays may have waited unhandled in
sensorTest. Other nodes' arrays handled meanwhile show the PC did take the topic: the driver's
absence then fails, as does a topic nobody else publishes (however busy the PC) and a silent
driver on a quiet PC.
"""
import time
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

from . import lag
from .base import Check, fmt
from .values.health import HealthValues, JointRow

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import HealthExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext

JOINT_PREFIX = 'naoqi_driver_joints:'
JOINTS_STATUS = 'naoqi_driver_joints:Status'
BATTERY_STATUS = 'naoqi_driver_battery:Status'
OK, WARN, ERROR = 0, 1, 2           # diagnostic_msgs/DiagnosticStatus levels
LEVELS = {OK: 'OK', WARN: 'WARN', ERROR: 'ERROR', 3: 'STALE'}
HOT_C, TOO_HOT_C = 68, 74           # the driver's levels (diagnostics.cpp:57-58), for the words only
BATTERY_WARN, BATTERY_ERROR = 60, 30    # the driver's battery levels (diagnostics.cpp:247-257)
WAIT = 5.0                          # --wait when not given (plan/settings.py's default)
# s more the window waits for the driver's first array on a busy PC: sensorTest's own backlog
# beside six busy loops on 2 cores reached 5.6 s (issue 41: "stale data ... 5.58 s"), so
# arrays sent within --wait may be handled up to that much later
BUSY_EXTRA = 6.0
HOTTEST = 3                         # joints named in the summary


def _kv(status: Any) -> Dict[str, str]:
    return {kv.key: kv.value for kv in status.values}


def _number(text: Optional[str]) -> Optional[float]:
    try:
        return float(text) if text is not None else None
    except ValueError:
        return None


def _flag(text: Optional[str]) -> Optional[bool]:
    # DiagnosticStatusWrapper::add<bool> writes "True" / "False"
    if text is None:
        return None
    return text.strip().lower() in ('true', '1')


class HealthCheck(Check):
    family = 'health'
    expect: 'HealthExpect'

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.found: Optional[HealthValues] = None
        self.wait = ctx.options.wait or WAIT
        self.arrays = 0                 # arrays carrying the driver's statuses
        self.others = 0                 # arrays from other nodes only
        self.joints: Dict[str, List[Any]] = {}      # joint -> [max temperature, worst level, message]
        self.battery: Optional[Dict[str, Any]] = None   # the latest battery status
        self.battery_worst = OK
        self.battery_worst_message = ''
        self.now = 0.0
        self.publishers: Optional[int] = None   # the most publishers the live source saw (None: a bag)
        self.busy = ''                  # why this PC counts as busy while nothing came ('' : not)
        self._began: Optional[float] = None     # monotonic start of the window (live)

    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        return [('Statuses', len(msg.status)),
                ('Names', ', '.join(s.name for s in msg.status[:3]) + (' ...' if len(msg.status) > 3 else ''))]

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        mine = False
        for status in msg.status:
            name = status.name
            if name == BATTERY_STATUS:
                mine = True
                kv = _kv(status)
                pct = _number(kv.get('Percentage'))
                self.battery = {'percent': int(pct) if pct is not None else None,
                                'charging': _flag(kv.get('Charging')),
                                'fully_charged': _flag(kv.get('Fully Charged')),
                                'level': int(status.level), 'message': status.message}
                if int(status.level) >= self.battery_worst:
                    self.battery_worst, self.battery_worst_message = int(status.level), status.message
            elif name.startswith(JOINT_PREFIX) and name != JOINTS_STATUS:
                mine = True
                joint = name[len(JOINT_PREFIX):]
                temp = _number(_kv(status).get('Temperature'))
                row = self.joints.setdefault(joint, [None, OK, 'OK'])
                if temp is not None and (row[0] is None or temp > row[0]):
                    row[0] = temp
                if int(status.level) >= row[1]:
                    row[1], row[2] = int(status.level), status.message
            elif name == JOINTS_STATUS:
                mine = True
        if mine:
            self.arrays += 1
        else:
            self.others += 1

    def window(self, duration: float) -> float:
        # room for the busy PC's extra wait; a healthy driver ends it within seconds (done())
        return max(duration, self.wait + BUSY_EXTRA)

    def observe_connections(self, n: int) -> None:
        """The live source's count of the topic's publishers (sensors/window.py)."""
        self.publishers = max(self.publishers or 0, n)

    def poll(self, elapsed: float) -> None:
        self.now = elapsed
        if self.publishers is None or self.arrays or self.others or self.busy:
            return
        now = time.monotonic()
        if self._began is None:
            self._began = now - elapsed
        self.busy = lag.pc_busy(self.own_lag, self._began, now)

    def _limit(self) -> float:
        """How long to wait for the driver's first array (module docstring)."""
        return self.wait + BUSY_EXTRA if self._unheard() else self.wait

    def _unheard(self) -> bool:
        """Nothing at all reached the window on a busy PC, from a topic with a publisher: the
        PC may have kept it (other nodes' arrays handled meanwhile say it did not)."""
        return bool(self.busy and self.publishers and not self.others)

    def done(self) -> bool:
        return self.arrays >= self.expect.arrays or (self.arrays == 0 and self.now >= self._limit())

    def settled(self) -> bool:
        return self.arrays >= self.expect.arrays

    def _rows(self) -> List[JointRow]:
        rows = [JointRow(j, round(v[0], 1) if v[0] is not None else None, LEVELS.get(v[1], str(v[1])), v[2])
                for j, v in self.joints.items()]
        return sorted(rows, key=lambda r: -(r.temperature_c if r.temperature_c is not None else -1e9))

    def finish(self) -> None:
        rows = self._rows()
        hot = [r for r in rows if r.level != 'OK']
        b = self.battery or {}
        values = HealthValues(self.arrays, b.get('percent'), b.get('charging'), b.get('fully_charged'),
                              LEVELS.get(self.battery_worst) if self.battery else None,
                              self.battery_worst_message or None,
                              rows[0].temperature_c if rows else None, rows[:HOTTEST], hot,
                              {r.joint: r.temperature_c for r in rows if r.temperature_c is not None} or None)
        self.found = values
        if not self.arrays and self._unheard():
            self.not_judged('PC busy: no naoqi_driver diagnostics on %s within %g s although the topic has '
                            'a publisher, but this PC was busy (%s): the driver\'s arrays may have waited '
                            'unhandled in sensorTest; test again when it is quieter'
                            % (self.plan.topic, self._limit(), self.busy))
            return
        if not self.arrays:
            others = (' (%d array%s from other nodes only)' % (self.others, '' if self.others == 1 else 's')
                      if self.others else '')
            self.fail('no naoqi_driver diagnostics on %s within %g s%s: the driver\'s diagnostics '
                      'are off (converters.diag.enabled in its boot_config.json) or naoqi_driver '
                      'is not running' % (self.plan.topic, self.wait, others))
            return
        self.notes.append(battery_text(values))
        self.notes.append(hottest_text(values))
        too_hot = [r for r in hot if r.level == 'ERROR']
        warm = [r for r in hot if r.level == 'WARN']
        if too_hot:
            self.fail('too hot (the driver\'s ERROR, %d °C and above): %s: let the robot cool down '
                      '(rest it with its stiffness off) before testing' % (TOO_HOT_C, _joints(too_hot)))
        if warm:
            self.warn('hot (the driver\'s WARN, %d-%d °C): %s' % (HOT_C, TOO_HOT_C, _joints(warm)))
        if self.battery is None:
            self.warn('no battery status (%s) from the driver' % BATTERY_STATUS)
        elif self.battery_worst >= ERROR:
            self.fail('battery almost empty: %s (the driver\'s ERROR, %d %% or less and not '
                      'charging): charge it before testing' % (_pct(values), BATTERY_ERROR))
        elif self.battery_worst == WARN:
            self.warn('battery discharging: %s (the driver warns at %d %% or less when not '
                      'charging)' % (_pct(values), BATTERY_WARN))
        if not self.joints:
            self.warn('no joint status (%s<joint>) from the driver' % JOINT_PREFIX)


def _joints(rows: List[JointRow]) -> str:
    return ', '.join('%s %s°C' % (r.joint, fmt(r.temperature_c, 1)) for r in rows)


def _pct(v: HealthValues) -> str:
    return '%s%% left' % ('?' if v.battery_percent is None else v.battery_percent)


def battery_text(v: HealthValues) -> str:
    """'battery 85%, not charging (driver: OK)'."""
    if v.battery_percent is None and v.charging is None:
        return 'battery: no status from the driver'
    state = 'fully charged' if v.fully_charged else 'charging' if v.charging else 'not charging'
    return 'battery %s%%, %s (driver: %s)' % ('?' if v.battery_percent is None else v.battery_percent,
                                               state, v.battery_level or '?')


def hottest_text(v: HealthValues) -> str:
    """'hottest joints: HipPitch 45°C, KneePitch 44°C, HeadYaw 40°C' (as the driver writes them)."""
    if not v.hottest:
        return 'hottest joints: no joint status from the driver'
    return 'hottest joints: ' + _joints(list(v.hottest))
