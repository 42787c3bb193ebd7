# Thin wrapper so the README's two commands do everything on a fresh Debian
# machine: install what is missing, configure, build, then render or test.
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=
# CI builds treat warnings as errors (RTT_WERROR); a user's build does not
ifeq ($(CI),true)
CMAKE_FLAGS += -DRTT_WERROR=ON
endif

.PHONY: all deps configure build demo test fuzz sanitize clean

all: build

deps:
	@bash ci/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > $(BUILD).configure.log 2>&1 || (cat $(BUILD).configure.log; exit 1)

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	./$(BUILD)/cli/rtt render scenes/demo.json --shadows multi:16 -o demo.png -o demo.exr
	@echo "demo: wrote demo.png and demo.exr"

# The suite runs twice: with the widest instruction set the CPU has, then
# with every kernel pinned to the SSE4.1 baseline (RTT_ISA=sse4), which any
# x86-64 rtt supports must pass too; the CI-only builds run once.
test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)
	cd $(BUILD) && RTT_ISA=sse4 ctest --output-on-failure -j $(JOBS) -E '^(fuzz_smoke|sanitize)$$'

fuzz: deps
	bash ci/fuzz-smoke.sh

sanitize: deps
	bash ci/sanitize.sh

clean:
	rm -rf $(BUILD) $(BUILD).configure.log
