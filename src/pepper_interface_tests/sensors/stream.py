"""The generic stream rules, one check for every sensor's topic, composed with the family's own.

Like diagnostic_updater's TopicDiagnostic (a FrequencyStatus and a TimeStampStatus ticked per
message), a window feeds each message to this StreamCheck and to the family's Check, and its
verdict is the worse of the two (sensors/window.py). The rules, each with its reason:

- Arrival: a message within --wait; otherwise the reason says which of: no publisher at all,
  the topic advertised with another type (both named), not in the bag, or a publisher that
  sends nothing. Event-driven families (Traits.periodic False): silence is normal, but a live
  topic with no publisher at all or advertised with another type fails as above.
- Type: every message is of an accepted type (subscriptions are rospy.AnyMsg), else it fails
  naming both types; a message that cannot be decoded or checked fails by name.
- Count and rate (periodic families): at least `min_messages`; the rate from receive times and
  the rate from header stamps inside the expected band (a rate within 10 % of an edge is a
  warning: possible, worth a look). Sim time: measured on /clock, and with /use_sim_time set
  but no /clock, nothing is judged but that (NO_CLOCK). From a bag: measured on the record
  time (`rosbag record` stamps a message with ros::Time::now(), the simulation time when it
  recorded under /use_sim_time); the JSON's stats.clock says which clock.
- Stamps: none zero, none going backwards (repeated ones are a warning), not older than
  `max_delay` nor more than `max_future` ahead of ROS time; a constant offset beyond them is
  named a clock offset (OFFSET_SPREAD), one of 1 s or more inside them is a warning.
  On sim time, ROS time is the last /clock tick this node received: when /clock reaches it
  late (a loaded machine, the first ticks while its subscription connects), a message stamped
  by the simulator at its current time looks ahead of it. So there a stamp ahead by more than
  `max_future` fails only when most messages are (SIM_FUTURE_SHARE: a publisher stamping with
  another clock is ahead in every message); a few are a warning naming the /clock lag.
  `frame_id` as configured.
- A publisher that stopped (periodic families): the last message more than
  max(1 s, max_gap_factor / rate_min) before the end of the window fails; shorter pauses above
  that threshold are warnings.
- Publishers: more than one node delivering on the topic is named; it fails the microphones
  (Traits.audio: two audio bridges interleave their buffers), elsewhere it is a warning.
"""
from typing import Any, Callable, Dict, List, Optional, Tuple

from ..plan import catalog
from ..sources import TopicInfo
from ..stats import StreamStats
from .base import Judgement, Tally
from .clock import WindowClock
from .families import Traits
from .lag import OwnLag, starved_hint

# Spread (max - min) of "ROS time at reception - header stamp" below which a delay beyond the
# limits is one constant offset between two clocks, not data getting old: network and driver
# latency vary by milliseconds to a few hundred ms, a stale or stuck stream's delay grows.
OFFSET_SPREAD = 1.0
# On sim time, the share of messages stamped beyond max_future ahead of the last /clock tick
# above which they fail (below it: /clock reached this node late, a warning; module docstring).
SIM_FUTURE_SHARE = 0.5

NO_CLOCK = ('/use_sim_time is true but nothing publishes /clock, so ROS time stands at 0 and no '
            'stamp or simulation-time rate can be judged: start the simulator (it publishes /clock), '
            'or clear a leftover setting with "rosparam set /use_sim_time false" and start again')


def clock_offset(delay: Optional[Dict[str, float]], max_delay: float, max_future: float) -> str:
    """The reason for header stamps a constant offset away from this computer's clock (the
    robot's clock not synchronised, e.g. an hour off after a time-zone mistake), or ''."""
    if not delay or delay['max'] - delay['min'] > OFFSET_SPREAD:
        return ''
    mean = delay['mean']
    if mean > max_delay:
        side = 'behind'
    elif -mean > max_future:
        side = 'ahead of'
    else:
        return ''
    return ('clock offset: header stamps are a constant %.1f s %s this computer\'s clock (spread %.2f s): '
            'the robot\'s clock is not synchronised with this one; sync both with chrony or ntp%s'
            % (abs(mean), side, delay['max'] - delay['min'],
               ' (or the driver stamps its data that late)' if side == 'behind' else ''))


def no_publisher_note(name: str) -> str:
    """' Note: ...' for a sensor whose missing publisher has a known cause, else ''."""
    hint = catalog.NO_PUBLISHER_HINTS.get(name)
    return ' Note: ' + hint if hint else ''


Lookup = Callable[[str], Optional[TopicInfo]]


class StreamCheck:
    """The generic rules over one topic's messages (see the module docstring)."""

    def __init__(self, sensor: catalog.Sensor, topic: Optional[str], expect: Any, traits: Traits,
                 clock: WindowClock) -> None:
        self.sensor, self.topic, self.expect, self.traits, self.clock = sensor, topic, expect, traits, clock
        self.stats = StreamStats()
        self.issues = Tally()                 # bad headers, undecodable or uncheckable messages
        self.wrong_types: Dict[str, int] = {}   # type name -> count
        self.received_type: Optional[str] = None
        self.publishers: List[str] = []       # caller ids of the nodes whose messages arrived, in order
        self.connections_seen = 0
        self.publisher_lost_at: Optional[float] = None
        self.own_lag: Optional[OwnLag] = None   # sensorTest's own lag on the topic (window.py)
        self._unjudged: List[str] = []          # what this PC was too busy to judge
        self.own: List[Tuple[float, float]] = []   # per delay: (handled at, thread busy since)

    # ---------------------------------------------------------------- per message
    def begin(self, now: float) -> None:
        self.stats.start = now

    def use_sim_clock(self) -> None:
        self.stats = StreamStats(start=self.clock.t0, clock='sim')

    def use_record_clock(self) -> None:
        self.stats.clock = 'record'

    def accept(self, type_name: str, conn: Optional[Dict[str, Any]]) -> bool:
        """Counts a message of a wrong type and returns False; else notes its publisher."""
        if not catalog.accepts_type(self.sensor, type_name):
            self.wrong_types[type_name] = self.wrong_types.get(type_name, 0) + 1
            return False
        self.received_type = type_name
        caller = (conn or {}).get('callerid')
        if caller and caller not in self.publishers:
            self.publishers.append(caller)
        return True

    def add(self, t_recv: float, ros_now: float, header: Any, own_since: Optional[float] = None) -> None:
        """A decoded message's receive time and header (None for a type without one), and
        since when its topic's thread had been busy (sensors/lag.py; None: not measured)."""
        self.sync_sim_start()
        stamp = header.stamp.to_sec() if header is not None else None
        self.stats.add(t_recv, stamp, ros_now if header is not None else None, ros_now)
        if len(self.own) < len(self.stats.delays):     # a delay was measured
            self.own.append((t_recv, t_recv if own_since is None else own_since))
        if header is not None:
            want = self.expect.frame_id
            if want and header.frame_id != want:
                self.issues.add('frame', 'frame_id is "%s", expected "%s"' % (header.frame_id, want))

    def sync_sim_start(self) -> None:
        """On sim time: the stats measure from the simulation time listening began at."""
        if self.stats.clock == 'sim' and self.stats.clock_start is None:
            self.stats.clock_start = self.clock.sim_start()

    def observe_connections(self, n: int, now: float) -> None:
        if n > 0:
            self.connections_seen = max(self.connections_seen, n)
        elif self.connections_seen and self.publisher_lost_at is None:
            self.publisher_lost_at = now - self.clock.began

    # ---------------------------------------------------------------- judging
    def provisional(self, count: int) -> List[str]:
        """Problems so far, for a running window (the caller holds the window's lock)."""
        return self.issues.reasons(count)

    def judge(self, elapsed: float, band: Optional[List[float]], lookup: Optional[Lookup],
              drives_itself: bool) -> Judgement:
        """The stream's reasons and warnings at the end of the window; `band` is the family's
        accepted rate, `lookup` asks the master (or the bag) about a silent topic."""
        self.sync_sim_start()
        reasons: List[str] = []
        warnings: List[str] = []
        self._unjudged = []
        if not drives_itself:
            skip = self._head_variant_skip(lookup)
            if skip:
                return Judgement([], [], skip)
            reasons += self._arrival_reasons(elapsed, lookup)
            if self.stats.count:
                reasons += self._stream_reasons(elapsed, band, warnings)
        reasons += self.issues.reasons(self.stats.count)
        self._publisher_reasons(reasons, warnings)
        return Judgement(reasons, warnings, None, list(self._unjudged))

    def _head_variant_skip(self, lookup: Optional[Lookup]) -> Optional[str]:
        """The SKIPPED reason of a silent topic absent from the robot because of its head
        variant (catalog.HEAD_VARIANT_SKIPS), when the robot shows that head; else None."""
        if self.stats.count or self.wrong_types or lookup is None:
            return None
        sign = catalog.head_sign_topic(self.sensor.name, self.topic)
        if sign is None:
            return None
        info = lookup(self.topic or '')
        if info is not None and info[1]:        # the topic itself has a publisher: judge it
            return None
        shown = lookup(sign)
        if shown is None or not shown[1]:       # no publisher (live) / not in the bag
            return None
        return catalog.head_skip_reason(self.sensor.name, sign)

    def _publisher_reasons(self, reasons: List[str], warnings: List[str]) -> None:
        if len(self.publishers) < 2 or self.traits.shared_topic:
            return
        text = '%d publishers deliver on %s: %s' % (len(self.publishers), self.topic,
                                                    ', '.join(self.publishers))
        if self.traits.audio:
            reasons.append(text + ' (two audio bridges running? start only one: '
                                  'launch_audio:=false for the CSSR naoqi_driver, or stop the other node)')
        else:
            warnings.append(text)

    def _arrival_reasons(self, elapsed: float, lookup: Optional[Lookup]) -> List[str]:
        reasons = self._arrival(elapsed, lookup)
        note = self.expect.silence_note
        if note and not self.stats.count and not self.wrong_types:
            reasons = [r + ' (%s)' % note for r in reasons]
        return reasons

    def _arrival(self, elapsed: float, lookup: Optional[Lookup]) -> List[str]:
        topic = self.topic or ''
        if self.wrong_types:
            types = ', '.join(sorted(self.wrong_types))
            return ['topic %s carries %s, expected %s' % (topic, types, catalog.expected_types(self.sensor))]
        if self.stats.count:
            return []
        info = lookup(topic) if lookup else None
        if not self.traits.periodic:
            # an event topic: silence is normal (nobody touched), a topic nobody publishes on a
            # live master or one advertised with another type is not; a bag records a topic only
            # once a message came (publishers None): silence there too
            if info is None:
                return []
            advertised, publishers = info
            if advertised and not catalog.accepts_type(self.sensor, advertised):
                return ['topic %s is advertised as %s, expected %s'
                        % (topic, advertised, catalog.expected_types(self.sensor))]
            if publishers == []:
                return ['no publisher on %s (is the driver running, and is the topic name right?%s)'
                        % (topic, no_publisher_note(self.sensor.name))]
            return []
        if info is None:
            return ['no message on %s within %.1f s' % (topic, elapsed)]
        advertised, publishers = info
        if advertised and not catalog.accepts_type(self.sensor, advertised):
            return ['topic %s is advertised as %s, expected %s'
                    % (topic, advertised, catalog.expected_types(self.sensor))]
        if publishers is None:
            return ['topic %s is not in the bag' % topic]
        if not publishers:
            return ['no publisher on %s (is the driver running, and is the topic name right?%s)'
                    % (topic, no_publisher_note(self.sensor.name))]
        return ['no message on %s within %.1f s although %s publishes it'
                % (topic, elapsed, ', '.join(publishers))]

    def _stream_reasons(self, elapsed: float, band: Optional[List[float]], warnings: List[str]) -> List[str]:
        s = self.stats
        out: List[str] = []
        if self.traits.periodic and s.count < self.expect.min_messages:
            out.append('only %d message%s in %.1f s (at least %d expected)'
                       % (s.count, '' if s.count == 1 else 's', elapsed, self.expect.min_messages))
        if self.clock.on_sim_time and self.clock.sim_t0 is None:
            # rospy keeps ROS time at 0 until /clock ticks: stamps, sim rates and windows
            # cannot be measured, and "1.8e9 s in the future" would blame the robot
            out.append(NO_CLOCK)
            return out
        if self.traits.periodic:
            self._rate_reasons(band, out, warnings)
        if not self.traits.shared_topic:   # many nodes' stamps interleave on a shared topic
            self._stamp_reasons(out, warnings)
        if self.traits.periodic:
            self._silence_reasons(elapsed, band, out, warnings)
        return out

    def _rate_reasons(self, band: Optional[List[float]], out: List[str], warnings: List[str]) -> None:
        s = self.stats
        if not band or s.count < 3:
            return
        lo, hi = band
        rate_label = 'rate (sim clock)' if s.clock == 'sim' else 'rate'
        lag = self.own_lag
        span = (s.recv[-1] - s.recv[0]) if s.recv else 0.0
        if s.clock != 'sim' and lag is not None and lag.probe is not None and lag.saturated(span) \
                and any(r is not None and r < lo for r in (s.rate, s.stamp_rate)):
            self._unjudged.append(
                'PC busy: rate %.2f Hz below the expected %g-%g Hz, but sensorTest could not keep up with this '
                'topic (%s over a %.1f s window: messages waiting in its full queue are dropped); test again '
                'when the PC is quieter' % (s.rate or 0.0, lo, hi, lag.describe(), span))
            return
        hint = starved_hint(lag) if s.clock != 'sim' else ''
        for label, rate in ((rate_label, s.rate), ('header stamp rate', s.stamp_rate)):
            if rate is not None and not (lo <= rate <= hi):
                low = rate < lo and hint
                out.append('%s %.2f Hz outside the expected %g-%g Hz%s' % (label, rate, lo, hi, hint if low else ''))
                hint = '' if low else hint     # said once
            elif rate is not None and label == rate_label and (rate < 1.1 * lo or rate > 0.9 * hi):
                # inside the band but within 10 % of an edge: possible, worth a look
                warnings.append('%s %.2f Hz near the edge of the expected %g-%g Hz' % (label, rate, lo, hi))

    def _stamp_reasons(self, out: List[str], warnings: List[str]) -> None:
        s, e = self.stats, self.expect
        if s.zero_stamps:
            out.append('%d message%s with a zero header stamp' % (s.zero_stamps, '' if s.zero_stamps == 1 else 's'))
        if s.backwards:
            out.append('header stamps went backwards %d time%s' % (s.backwards, '' if s.backwards == 1 else 's'))
        if s.repeated:
            warnings.append('%d repeated header stamp%s' % (s.repeated, '' if s.repeated == 1 else 's'))
        delay = s.delay_summary()
        offset = clock_offset(delay, e.max_delay, e.max_future)
        if offset:
            out.append(offset)
        elif delay and delay['max'] - delay['min'] <= OFFSET_SPREAD and abs(delay['mean']) >= 1.0:
            # a constant offset inside the limits: possible (clocks a second apart), worth a look
            warnings.append('clock offset: header stamps a constant %.1f s %s this computer\'s clock '
                            '(within max_delay %g s / max_future %g s; sync both clocks with chrony)'
                            % (abs(delay['mean']), 'behind' if delay['mean'] > 0 else 'ahead of',
                               e.max_delay, e.max_future))
        if delay and not offset:
            if delay['max'] > e.max_delay:
                self._stale(delay['max'], out)
            if -delay['min'] > e.max_future:
                ahead = sum(1 for d in s.delays if -d > e.max_future)
                if s.clock == 'sim' and ahead <= SIM_FUTURE_SHARE * len(s.delays):
                    warnings.append('%d of %d header stamps up to %.2f s ahead of the last /clock tick '
                                    'received (max_future %g s): /clock reached this node late'
                                    % (ahead, len(s.delays), -delay['min'], e.max_future))
                else:
                    out.append('header stamps up to %.2f s in the future (clock skew?)' % -delay['min'])

    def _stale(self, worst: float, out: List[str]) -> None:
        """Stamps older than max_delay: the sensor's, unless every such delay is explained by
        how long its message waited in this process (sensors/lag.py), or the PC was busy
        (lag.busy) and the same stream came with fresh stamps when sensorTest kept up (its
        smallest delay within max_delay: a driver stamping old data is old in every message):
        then NOT JUDGED."""
        limit = self.expect.max_delay
        lag = self.own_lag
        own = None
        if lag is not None and len(self.own) == len(self.stats.delays):
            own = max(d - lag.wait(t, since) for d, (t, since) in zip(self.stats.delays, self.own))
        if own is not None and own <= limit and lag is not None and lag.longest > 0:
            self._unjudged.append(
                'PC busy: header stamps up to %.2f s behind ROS time (at most %g s), but the messages '
                'waited in sensorTest itself (%s): without that wait they were at most %.2f s old; '
                'test again when the PC is quieter' % (worst, limit, lag.describe(), max(0.0, own)))
            return
        freshest = min(self.stats.delays) if self.stats.delays else None
        if lag is not None and lag.probe is not None and lag.busy and freshest is not None and freshest <= limit:
            self._unjudged.append(
                'PC busy: header stamps up to %.2f s behind ROS time (at most %g s) while this PC was busy (%s), '
                'and %.2f s when sensorTest kept up: the delay is this PC\'s, not the sensor\'s; test again '
                'when the PC is quieter' % (worst, limit, lag.describe(), max(0.0, freshest)))
            return
        out.append('stale data: header stamps up to %.2f s behind ROS time (at most %g s)' % (worst, limit))

    def _silence_reasons(self, elapsed: float, band: Optional[List[float]], out: List[str],
                         warnings: List[str]) -> None:
        """A publisher that stopped: the last message long before the end of the window."""
        s, clock = self.stats, self.clock
        if s.clock == 'sim' and clock.sim_stopped_at is not None and s.clock_recv:
            silence = clock.sim_stopped_at - s.clock_recv[-1]
            span = s.clock_recv[-1] - s.clock_recv[0]
        else:
            silence = (clock.began + elapsed) - s.recv[-1]
            span = s.recv[-1] - s.recv[0]
        lo_rate = band[0] if band else None
        threshold = max(1.0, self.expect.max_gap_factor / lo_rate) if lo_rate else 2.0
        lag = self.own_lag
        stalled = lag.probe.stalled(s.recv[-1], clock.began + elapsed) \
            if lag is not None and lag.probe is not None and s.clock != 'sim' else 0.0
        if silence > threshold and silence - stalled <= threshold and lag is not None:
            self._unjudged.append(
                'PC busy: nothing for the last %.1f s of the window, but sensorTest itself did not run '
                'for %.1f s of them (%s); test again when the PC is quieter' % (silence, stalled, lag.describe()))
        elif silence > threshold:
            lost = ' (publisher left at %.1f s)' % self.publisher_lost_at \
                if self.publisher_lost_at is not None else ''
            out.append('messages stopped %.1f s after the first one; nothing for the last %.1f s%s'
                       % (span, silence, lost))
        gaps = s.gaps(threshold)
        if gaps:
            longest = max(gaps, key=lambda g: g[1])
            warnings.append('%d pause%s longer than %.2f s (longest %.2f s at %.1f s)'
                            % (len(gaps), '' if len(gaps) == 1 else 's', threshold, longest[1], longest[0]))

