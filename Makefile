# The two commands of the README: `make run` and `make test`. Everything else is for developers.
JOBS ?= $(shell nproc)
BUILD ?= build/release
PORT ?= 8080

.PHONY: run run-janus run-labs test setup build asan bench clean fuzz

setup:
	@bash scripts/setup.sh

build: setup
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release > /dev/null
	@cmake --build $(BUILD) -j $(JOBS)

run: build
	@$(BUILD)/labodrone serve --port $(PORT)

# The lab with its video also through Janus (WebRTC fan-out for many spectators); `make run-labs
# LABS=3`: three labs behind one front (docs/web.md "Many viewers and several labs").
LABS ?= 3
run-janus: build
	@LABS=1 PORT=$(PORT) BUILD=$(BUILD) bash scripts/janus/run_labs.sh
run-labs: build
	@LABS=$(LABS) PORT=$(PORT) BUILD=$(BUILD) bash scripts/janus/run_labs.sh

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# Tests under AddressSanitizer + UndefinedBehaviorSanitizer.
asan: setup
	@cmake -S . -B build/asan -DCMAKE_BUILD_TYPE=Debug -DLABO_SANITIZE=ON > /dev/null
	@cmake --build build/asan -j $(JOBS)
	@cd build/asan && ctest --output-on-failure -j $(JOBS)

# libFuzzer harnesses for the AR.Drone parsers (navdata, PaVE, AT), FUZZ_SECONDS each.
FUZZ_SECONDS ?= 60
fuzz:
	@bash scripts/fuzz.sh $(FUZZ_SECONDS)

clean:
	rm -rf build
