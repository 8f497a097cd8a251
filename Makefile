# The two commands of the README: `make run` and `make test`. Everything else is for developers.
JOBS ?= $(shell nproc)
BUILD ?= build/release
PORT ?= 8080

.PHONY: run test setup build asan bench clean fuzz

setup:
	@bash scripts/setup.sh

build: setup
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release > /dev/null
	@cmake --build $(BUILD) -j $(JOBS)

run: build
	@$(BUILD)/labodrone serve --port $(PORT)

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
