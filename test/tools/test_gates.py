"""The minimum-Python gate (tools/vermin.sh, run by tools/gates.sh): the project passes it, and a
control shows it is not blind: Python 3.9 calls the package once made (os.waitstatus_to_exitcode
in media/recording.py, Ubuntu 20.04's Python 3.8 has no such function) are flagged, the 3.8
spellings that replaced them are not."""
import os
import subprocess

from rosmaster import ROOT

VERMIN = os.path.join(ROOT, 'tools', 'vermin.sh')


def vermin(*files):
    return subprocess.run([VERMIN] + [str(f) for f in files], capture_output=True, text=True,
                          timeout=240)


def test_the_project_needs_no_more_than_python38_and_the_capture_side_27():
    res = vermin()
    assert res.returncode == 0, res.stdout + res.stderr


def test_the_gate_flags_python39_calls_and_passes_their_38_spellings(tmp_path):
    new = tmp_path / 'new.py'
    new.write_text('import os\n\ndef code(status: int) -> dict[str, int]:\n'
                   '    return {"rc": os.waitstatus_to_exitcode(status)}\n\n'
                   'print("sensorTest".removeprefix("sensor"))\n')
    res = vermin(new)
    assert res.returncode != 0, res.stdout
    for what in ('os.waitstatus_to_exitcode', 'str.removeprefix', 'dict[..]'):
        assert what in res.stdout, (what, res.stdout)
    old = tmp_path / 'old.py'
    old.write_text('import os\nfrom typing import Dict\n\ndef code(status: int) -> Dict[str, int]:\n'
                   '    return {"rc": os.WEXITSTATUS(status)}\n\n'
                   'print("sensorTest"[len("sensor"):])\n')
    res = vermin(old)
    assert res.returncode == 0, res.stdout
