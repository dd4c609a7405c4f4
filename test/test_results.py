"""The run's result model (results.py): the exit code from the verdicts."""
from pepper_interface_tests.results import FAIL, PASS, SKIPPED, RunResult, SensorResult


def test_exit_codes():
    def run(*verdicts, interrupted=False):
        r = RunResult(platform='robot', mode='parallel', start=0.0, interrupted=interrupted)
        r.sensors = [SensorResult(name=str(i), title='', topic=None, msg_type='', verdict=v)
                     for i, v in enumerate(verdicts)]
        return r.exit_code
    assert run(PASS, SKIPPED, PASS) == 0          # SKIPPED counts as passed
    assert run(SKIPPED) == 0 and run() == 0
    assert run(PASS, FAIL, SKIPPED) == 1
    assert run(PASS, interrupted=True) == 130
