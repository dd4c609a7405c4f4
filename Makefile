# make demo   set everything up, then run sensorTest (parallel, every robot sensor) against the
#             built-in Pepper emulator through the real NAOqi audio bridge
# make test   set everything up, then run the whole test suite (pytest + rostest)
# make setup  only set up (Debian packages, .venv, catkin workspace in build/)
.PHONY: demo test setup bench clean

demo:
	@tools/setup.sh
	@tools/demo.sh

test:
	@tools/setup.sh --test
	@tools/run-tests.sh

setup:
	@tools/setup.sh

bench:
	@tools/setup.sh
	@bash -c 'source tools/env.sh && python scripts/sensorTestBenchmark'

clean:
	rm -rf build .venv .stamps
