# Convenience wrapper around CMake.  `make` builds; `make help` lists the targets.
.DEFAULT_GOAL := build
PREFIX       ?= /usr/local
FUZZ_SECONDS ?= 30
FUZZ_SEED    ?= 0
JOBS         ?= $(shell nproc)
# make mutate-diff / mutate-gen (scripts/mutagen.py)
BASE          ?= auto
MUTATE_BUDGET ?= 0
MUTATE_SAMPLE ?= 100
MUTATE_ARGS   ?=
# make coverage fails below this branch coverage of src/ (percent)
COVERAGE_MIN_BRANCH ?= 85
# -Werror for developers and CI (CI=true), not for users: a newer compiler's new warning
# must not break their build.  `make WERROR=ON` turns it on anywhere.
WERROR       ?= $(if $(CI),ON,OFF)
BUILD_TYPE   ?= RelWithDebInfo
# The interpreter the Python package is for: Debian's, where python3-numpy and python3-cffi are
PYTHON       ?= $(shell test -x /usr/bin/python3 && echo /usr/bin/python3 || echo python3)
FUZZERS      := fuzz_exr fuzz_hdr fuzz_pfm fuzz_png fuzz_scene fuzz_luminaire fuzz_ies fuzz_ldt
FORMAT_FILES  = $(shell find include src tools tests fuzz bench -type f \
                  \( -name '*.c' -o -name '*.h' -o -name '*.cpp' \) 2>/dev/null | sort)

.PHONY: help deps build release run python-dev test sanitize fuzz format format-check bench install blender-addon clean mutate coverage \
        mutate-diff mutate-gen options-doc

help:
	@echo "targets: deps build release run test sanitize fuzz format format-check bench install clean mutate coverage mutate-diff mutate-gen python-dev blender-addon options-doc"
	@echo "  make mutate-diff BASE=auto|last-landing|REV MUTATE_BUDGET=seconds (0: none)"
	@echo "  make mutate-gen MUTATE_SAMPLE=$(MUTATE_SAMPLE) (0: every mutant of src/, days)"
	@echo "  make fuzz FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_SEED=$(FUZZ_SEED) (0: a new seed each run)"
	@echo "  make install PREFIX=$(PREFIX)"

deps:
	scripts/install-deps.sh

build: deps
	@cmake -S . -B build -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DLUMIS_WERROR=$(WERROR) >/dev/null
	cmake --build build -j$(JOBS)

# The optimised build a user makes (-O3), with the CI's warnings as errors: gcc warns
# about more at -O3 (e.g. -Wmaybe-uninitialized) than at -O2.
release: deps
	cmake -S . -B build-release -DCMAKE_BUILD_TYPE=Release -DLUMIS_WERROR=$(WERROR) >/dev/null
	cmake --build build-release -j$(JOBS)

# run and install build the executable and its libraries only (with the shared ones the
# Python package loads): the tests and benchmarks take minutes more on a small machine.
run: deps
	@cmake -S . -B build -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DLUMIS_WERROR=$(WERROR) >/dev/null
	cmake --build build -j$(JOBS) --target lumis-cli lumis-python
	@$(MAKE) --no-print-directory python-dev
	./build/lumis demo

# `import lumis` from anywhere, on this checkout (an editable install, as pip's -e makes one):
# a .pth file in the user's site-packages names python/, whose package finds the libraries
# in build/.  `make install` installs a copy instead.
python-dev:
	@site=$$($(PYTHON) -m site --user-site) && mkdir -p "$$site" && \
	  echo "$(CURDIR)/python" > "$$site/lumis-dev.pth" && \
	  echo "python: $(PYTHON) imports lumis from $(CURDIR)/python ($$site/lumis-dev.pth)"

test: build
	@scripts/fetch-data.sh || echo "warning: scripts/fetch-data.sh failed; the data tests will skip" >&2
	ctest --test-dir build --output-on-failure -j2

sanitize: deps
	cmake -S . -B build-asan -DLUMIS_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug -DLUMIS_BUILD_BENCH=OFF \
	  -DLUMIS_WERROR=$(WERROR)
	cmake --build build-asan -j$(JOBS)
	@scripts/fetch-data.sh || echo "warning: scripts/fetch-data.sh failed; the data tests will skip" >&2
	@# the output sweep preloads a signal shim, which ASan refuses to run beside; the
	@# consumer tests (three.js, Blender) test the files, not the code: once, in 'make test'
	ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --test-dir build-asan --output-on-failure -j2 -LE 'sweep|consumer'

fuzz: deps
	CC=clang CXX=clang++ cmake -S . -B build-fuzz -DLUMIS_FUZZ=ON -DLUMIS_WERROR=$(WERROR) \
	  -DLUMIS_BUILD_TESTS=OFF -DLUMIS_BUILD_BENCH=OFF
	cmake --build build-fuzz -j$(JOBS)
	build-fuzz/fuzz/fuzz_make_corpus build-fuzz/corpus
	@# the real files of the test corpus too (tests/data/photometric/README.md)
	@for f in tests/data/photometric/*.ies tests/data/photometric/*.ldt; do \
	  [ -f "$$f" ] && cp "$$f" "build-fuzz/corpus/$${f##*.}/real-$${f##*/}" || true; done
	@for f in $(FUZZERS); do fmt=$${f#fuzz_}; log=build-fuzz/$$f.log; \
	  mkdir -p build-fuzz/artifacts/$$fmt; echo "== $$f: $(FUZZ_SECONDS) s (log: $$log)"; \
	  if build-fuzz/fuzz/$$f build-fuzz/corpus/$$fmt -max_total_time=$(FUZZ_SECONDS) \
	       -rss_limit_mb=2048 -malloc_limit_mb=512 -seed=$(FUZZ_SEED) -print_final_stats=1 -artifact_prefix=build-fuzz/artifacts/$$fmt/ \
	       >$$log 2>&1; then grep -E '^(Done|stat::(average_exec|new_units|peak_rss))' $$log; \
	  else tail -n 80 $$log; echo "$$f FAILED; reproducer: build-fuzz/artifacts/$$fmt/"; exit 1; fi; \
	done

# Mutation testing: each mutant of tests/mutants/ applied in turn against its module's tests
# (tests/mutants/README.md).  make mutate MODULES="core io" for some modules.
mutate: deps
	scripts/mutate.sh $(MODULES)

# Generated mutants (scripts/mutagen.py, needs python3-clang-14: scripts/install-deps.sh --dev):
# mutants made from the AST of the lines changed since BASE (committed or not), each run against
# its module's tests; survivors reported with file and line, not failing (tests/mutants/README.md).
# BASE=auto: the merge base with main, or HEAD~1 on main; last-landing: what CI uses.
# mutate-gen: all of src/, a fixed sample of MUTATE_SAMPLE mutants (its score in the README).
mutate-diff: deps
	nice -n 10 scripts/mutagen.py diff --base $(BASE) --budget $(MUTATE_BUDGET) $(MUTATE_ARGS)

mutate-gen: deps
	nice -n 10 scripts/mutagen.py all --sample $(MUTATE_SAMPLE) --budget $(MUTATE_BUDGET) $(MUTATE_ARGS)

# Line, function and branch coverage of src/ over the whole suite (gcov + gcovr): a summary,
# the public functions no test calls, and an HTML report in build-coverage/coverage/.
# gcovr's parser trips on the negative branch counts that parallel runs can leave in .gcda
# files, hence --gcov-ignore-parse-errors.
coverage: deps
	cmake -S . -B build-coverage -DLUMIS_COVERAGE=ON -DCMAKE_BUILD_TYPE=Debug -DLUMIS_BUILD_BENCH=OFF \
	  -DLUMIS_WERROR=$(WERROR) >/dev/null
	cmake --build build-coverage -j$(JOBS)
	find build-coverage -name '*.gcda' -delete
	@scripts/fetch-data.sh || echo "warning: scripts/fetch-data.sh failed; the data tests will skip" >&2
	@# the consumer tests (three.js, Blender) test the files; test_io and test_cli cover the code
	ctest --test-dir build-coverage --output-on-failure -j2 -LE consumer
	@mkdir -p build-coverage/coverage
	gcovr -r . --object-directory build-coverage --filter 'src/' --gcov-ignore-parse-errors \
	  --exclude-unreachable-branches --exclude-throw-branches -j$(JOBS) \
	  --html-details build-coverage/coverage/index.html --json build-coverage/coverage/coverage.json \
	  --print-summary
	scripts/coverage-check.py build-coverage/coverage/coverage.json --min-branch $(COVERAGE_MIN_BRANCH)
	@echo "coverage: build-coverage/coverage/index.html"

format:
	@echo "clang-format -i: $(words $(FORMAT_FILES)) files"
	@clang-format -i $(FORMAT_FILES)

format-check:
	@echo "clang-format --dry-run --Werror: $(words $(FORMAT_FILES)) files"
	@clang-format --dry-run --Werror $(FORMAT_FILES)

# docs/options.md from the commands' option tables (tools/lumis; the test
# options_documented fails when it is stale)
options-doc:
	@cmake -S . -B build -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DLUMIS_WERROR=$(WERROR) >/dev/null
	cmake --build build -j$(JOBS) --target lumis-cli
	scripts/options-doc.sh build/lumis

bench: build
	./build/bench/bench_info
	./build/bench/bench_pick
	./build/bench/bench_render

# The optimised Release build (-O3, no debug information) is what a user installs; it is
# reconfigured with the prefix first: the installed lumis.pc / lumis-io.pc name it.
install: deps
	cmake -S . -B build-release -DCMAKE_BUILD_TYPE=Release -DLUMIS_WERROR=$(WERROR) \
	  -DCMAKE_INSTALL_PREFIX=$(PREFIX) >/dev/null
	cmake --build build-release -j$(JOBS) --target lumis-cli lumis-python
	cmake --install build-release --prefix $(PREFIX)
	@if [ -w /etc/ld.so.cache ] && command -v ldconfig >/dev/null; then ldconfig; fi

# The Blender add-on as the zip Blender's preferences install (docs/blender.md).
blender-addon:
	scripts/blender-addon.sh build/lumis_lights.zip

clean:
	rm -rf build build-release build-asan build-fuzz build-mutate build-mutgen build-coverage
