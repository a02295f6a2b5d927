# ddmr-hil: the two commands a user needs are `make run` and `make test`.
# Each installs what is missing (Debian packages, as root), builds and runs.

BUILD      ?= build
BUILD_ASAN ?= build-asan
BUILD_FUZZ ?= build-fuzz
FUZZ_SECONDS ?= 600
FUZZ_TARGETS = plant_yaml scenario_yaml eeprom_log report_parser elf_loader
BUILD_TYPE ?= RelWithDebInfo
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)
CASE       ?= 1
OUT        ?= out/run-case$(CASE)

.PHONY: all deps configure build build-run build-asan run test test-asan bench fuzz lint docs-parts clean help

all: build

help:
	@echo "make run     install deps, build, run case $(CASE) (the thesis's 0.6 m circle) in the HIL -> $(OUT)/"
	@echo "make test    install deps, build, run the static checks (make lint) and every test (ctest)"
	@echo "make bench   install deps, build, run the benchmarks (build/bench/results.json)"
	@echo "make lint    cppcheck, clang-tidy (.clang-tidy: functions <= 150 lines) and files <= 600 lines; any finding fails"
	@echo "            (clang-tidy skips files unchanged since a clean run; LINT_CACHE=0 checks all)"
	@echo "make docs-parts  write the parts table (docs/boards.md) and parts schema from \`ddmr-hil parts\`"
	@echo "make fuzz    libFuzzer (clang) on each fuzz target for FUZZ_SECONDS (default 600) s"
	@echo "make deps    install the Debian packages the project needs (apt-get, as root)"
	@echo "make clean   remove $(BUILD)/, $(BUILD_ASAN)/ and out/"

deps:
	@sh tools/install-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE)

configure: deps $(BUILD)/CMakeCache.txt

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# What `make run` runs, and only that: the front end and the reference
# firmware (not the tests, benchmarks and mutated sketches `make build` adds).
build-run: configure
	cmake --build $(BUILD) -j $(JOBS) --target ddmr-hil ddmr_firmware

# The HIL run, its comparison with the host simulation (exit 1 = beyond
# tolerance: reported, the report is still written; 2 = error: stop), and the
# report with its plots.
run: build-run
	./$(BUILD)/ddmr-hil run --case $(CASE) --out $(OUT)
	@rc=0; ./$(BUILD)/ddmr-hil compare $(OUT) || rc=$$?; \
	    if [ $$rc -gt 1 ]; then exit $$rc; fi; \
	    if [ $$rc -eq 1 ]; then echo "compare: the firmware log is beyond tolerance of the simulation (see $(OUT)/compare.json)"; fi
	./$(BUILD)/ddmr-hil report $(OUT)
	@echo "report: $(OUT)/report.md (plots beside it; summary.json, compare.json, truth.csv, firmware.csv, eeprom_log.csv, uart.txt)"

# The static checks (make lint), every test, then every test again under
# AddressSanitizer + UBSan + LeakSanitizer in a separate build tree.
test: build
	$(MAKE) lint
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)
	$(MAKE) test-asan

$(BUILD_ASAN)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_ASAN) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDDMR_SANITIZE=ON \
	    -DDDMR_BUILD_BENCH=OFF -DDDMR_BUILD_MUTANTS=OFF

build-asan: deps $(BUILD_ASAN)/CMakeCache.txt
	cmake --build $(BUILD_ASAN) -j $(JOBS)

# The sanitizer pass skips tests labelled slow (the mutation test runs the
# whole scenario suite seven times); they run in the normal tree above, and the
# sanitizer tree does not build their mutated sketches (firmware, not host
# code: nothing for the sanitizers to check, three minutes of arduino-builder).
# It also skips tests labelled external, whose time goes into other programs
# (the Python tests; arduino-builder and matplotlib runs): they run no host
# code of ours that tests kept in both passes do not run.
test-asan: build-asan
	cd $(BUILD_ASAN) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 \
	    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ctest --output-on-failure -j $(JOBS) -LE 'slow|external'

# Speed goals are measured here, never by timed tests. Results in $(BUILD)/bench/.
bench: build
	mkdir -p $(BUILD)/bench
	./$(BUILD)/tests/bench/ddmr_plant_bench --benchmark_out=$(BUILD)/bench/plant.json \
	    --benchmark_out_format=json
	./$(BUILD)/tests/bench/ddmr_hil_bench --benchmark_out=$(BUILD)/bench/hil.json \
	    --benchmark_out_format=json --ratio_out=$(BUILD)/bench/hil_ratio.json
	./$(BUILD)/tests/bench/ddmr_world_bench --benchmark_out=$(BUILD)/bench/world.json \
	    --benchmark_out_format=json
	./$(BUILD)/tests/bench/ddmr_sim_bench --benchmark_out=$(BUILD)/bench/sim.json \
	    --benchmark_out_format=json
	./$(BUILD)/tests/bench/ddmr_calibrate_bench --benchmark_out=$(BUILD)/bench/calibrate.json \
	    --benchmark_out_format=json
	PYTHONPATH=$(BUILD)/python /usr/bin/python3 tools/python/bench/bench_api.py --build $(BUILD) \
	    --out $(BUILD)/bench/python.json
	PYTHONPATH=$(BUILD)/python /usr/bin/python3 tools/python/examples/monte_carlo_circle.py \
	    --firmware $(BUILD)/firmware/ddmr_tracking.elf --plants 200 --out $(BUILD)/bench/monte_carlo.json
	/usr/bin/python3 tools/python/bench/bench_fast_forward.py --build $(BUILD) --out $(BUILD)/bench/fast_forward.json
	/usr/bin/python3 tools/bench_table.py $(BUILD)/bench

# Static checks of the project's own code (plant/, hil/, tools/), part of
# `make test`; any finding fails. cppcheck: warning, performance, portability
# (inline suppressions give their reason). clang-tidy: the checks in
# .clang-tidy over compile_commands.json (every configure writes it), each
# warning an error, one file per process, $(JOBS) at once; its stderr (the
# per-file counts of warnings in system headers) goes to
# $(BUILD)/clang-tidy.stderr and is shown, without those counts, on failure.
# Each file goes through tools/cached_clang_tidy.py: a file whose preprocessed
# text, compile command, .clang-tidy, clang-tidy version and arguments all
# match an earlier clean run is not checked again (the cache is in
# ${XDG_CACHE_HOME:-~/.cache}/ddmr-hil/clang-tidy/; files with findings are
# never cached). LINT_CACHE=0 runs clang-tidy on every file.
LINT_CACHE ?= 1
LINT_TIDY = $(if $(filter 0,$(LINT_CACHE)),clang-tidy,/usr/bin/python3 tools/cached_clang_tidy.py --source-root=$(CURDIR))
LINT_SOURCES = $(wildcard plant/*.cpp hil/*.cpp hil/parts/*.cpp tools/*.cpp tools/calibrate/*.cpp tools/common/*.cpp tools/scenario/*.cpp tools/hostsim/*.cpp tools/python/*.cpp)
lint: configure
	@cmake -S . -B $(BUILD) >/dev/null  # compile_commands.json up to date with new sources
	sh tools/check_file_sizes.sh 600 plant hil tools
	cppcheck --enable=warning,performance,portability --std=c++17 --language=c++ --inline-suppr \
	    --suppress=missingIncludeSystem --error-exitcode=1 --quiet -I . -I tools plant hil tools
	@echo "clang-tidy: $(words $(LINT_SOURCES)) files, $(JOBS) at once"
	@printf '%s\n' $(LINT_SOURCES) | xargs -P $(JOBS) -n 1 $(LINT_TIDY) -p $(BUILD) --quiet \
	    --warnings-as-errors='*' 2>$(BUILD)/clang-tidy.stderr || \
	    { grep -v 'warnings* generated\.$$' $(BUILD)/clang-tidy.stderr >&2; echo "clang-tidy: findings above" >&2; exit 1; }

# The docs made from the part registry: docs/boards.md's parts table (between
# its parts-table markers) and docs/schema/board.schema.json's
# properties.parts.items, from `ddmr-hil parts --markdown` and `--schema`.
# Run it after adding or changing a part type; the tests
# (tests/tools/parts_command_test.cpp) fail until it has been.
docs-parts: configure
	cmake --build $(BUILD) -j $(JOBS) --target ddmr-hil
	/usr/bin/python3 tools/update_parts_docs.py ./$(BUILD)/ddmr-hil

# libFuzzer (clang) on each target for FUZZ_SECONDS, starting from the
# committed corpus (tests/fuzz/corpus/<target>); new inputs go to
# $(BUILD_FUZZ)/corpus/<target>. `make test` replays the committed corpus.
fuzz: deps
	command -v clang++ >/dev/null 2>&1 || DEBIAN_FRONTEND=noninteractive apt-get install -y -q clang
	cmake -S . -B $(BUILD_FUZZ) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DCMAKE_C_COMPILER=clang \
	    -DCMAKE_CXX_COMPILER=clang++ -DDDMR_FUZZ=ON -DDDMR_BUILD_BENCH=OFF
	cmake --build $(BUILD_FUZZ) -j $(JOBS) --target $(addprefix ddmr_fuzz_,$(FUZZ_TARGETS))
	set -e; for t in $(FUZZ_TARGETS); do \
	    mkdir -p $(BUILD_FUZZ)/corpus/$$t; \
	    ./$(BUILD_FUZZ)/tests/fuzz/ddmr_fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
	        $(BUILD_FUZZ)/corpus/$$t tests/fuzz/corpus/$$t; \
	done

clean:
	rm -rf $(BUILD) $(BUILD_ASAN) $(BUILD_FUZZ) out
