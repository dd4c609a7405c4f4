# make demo   set everything up, then run sensorTest (parallel, every robot sensor) against the
#             built-in Pepper emulator through the real NAOqi audio bridge
# make test   set everything up, then run the gates (ruff, mypy) and the whole test suite
#             (pytest + rostest: unit, integration and slow tiers)
# make test-fast  only the unit tier (pure tests, no ROS master, under 8 s of CPU): pytest -m unit
# make lint   only the gates (ruff and mypy, configured in pyproject.toml)
# make setup  only set up (Debian packages, .venv, catkin workspace in build/)
# make docs   regenerate docs/options.md from sensorTest's options, and the sensor tables, name lists
#             and topics/input files' sensor lines from plan/declaration.py (tests fail when stale)
# make bench  the benchmark (docs/benchmark.md): listening and recording next to rostopic hz,
#             then reading a 60 s recording in three forms next to a deserializing read, one
#             recording with the driver's /tf and one of the sensors alone
# make bench-recording  only the reading of recordings
.PHONY: demo test test-fast lint setup docs bench bench-recording clean

demo:
	@tools/setup.sh
	@tools/demo.sh

test:
	@tools/setup.sh --test
	@tools/run-tests.sh

test-fast:
	@tools/setup.sh
	@tools/run-tests.sh --fast

lint:
	@tools/setup.sh
	@tools/gates.sh

setup:
	@tools/setup.sh

docs:
	@tools/setup.sh
	@bash -c 'source tools/env.sh && python tools/gen_options.py && python tools/gen_sensors.py'

bench:
	@tools/setup.sh
	@bash -c 'source tools/env.sh && python tools/benchmark/sensor_test_benchmark.py --runs 2; a=$$?; \
	  python tools/benchmark/recording_benchmark.py; b=$$?; exit $$(( a > b ? a : b ))'

bench-recording:
	@tools/setup.sh
	@bash -c 'source tools/env.sh && python tools/benchmark/recording_benchmark.py'

clean:
	rm -rf build .venv .stamps
