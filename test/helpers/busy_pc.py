"""What a healthy robot may say on a busy PC (issue 41, docs/checks.md "On a busy PC and over
WiFi"): warnings that name a pause in delivery, and NOT JUDGED rows whose every reason names
the PC. Tests of healthy runs accept these and nothing else; a FAIL is always a failure."""
import re

# the warnings a busy PC makes true: pauses of the delivery (sensors/stream.py,
# sensors/audio.py), frames too far apart to follow the head (motion/rules.py)
DELIVERY = re.compile(r'pauses? longer than|gaps? in the audio stream|not judged on the head')


def sensor_warnings(row):
    """A row's warnings less those that name a pause in delivery."""
    return [w for w in row.get('warnings', []) if not DELIVERY.search(w)]


def healthy(row):
    """PASS, or NOT JUDGED with every reason naming the PC (sensors/lag.py)."""
    if row['verdict'] == 'PASS':
        return True
    return (row['verdict'] == 'NOT JUDGED' and bool(row['reasons'])
            and all(r.startswith('PC busy: ') for r in row['reasons']))
