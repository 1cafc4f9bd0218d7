# VLF — the two set-up commands and a few conveniences.
#   make demo   install dependencies, Release build, run the main job on the default scene
#   make test   install dependencies, check formatting, build, run every test (ctest)
BUILD       ?= build
ASAN_BUILD  ?= build-asan
JOBS        ?= $(shell nproc)
ASAN_TEST_SET ?= input
SCENE       ?= scenes/cornell-mirrors.json
DEMO_ARGS   ?= --quality preview
OUT         ?= out
# The sanitized build's tests are the input set of tests/CMakeLists.txt (VLF_TEST_SET=input),
# the command-line contract and the schema's refusals. Left to the Release build: MPI's (Open
# MPI's own allocations are not ASan-clean), and four accuracy tests that run, at a finer
# resolution, the code the input set's smaller smooth-surface, glass and lamp tests run
# (LedgerClosesWithSmoothGlassAndMirror, CurvedMirrorsAndGlassHandTheLampsLightToTheShot,
# LedgerClosesWithPointAndSpotThroughGlass, Checkpoint.SmoothGlass...): they were half the
# sanitized run's 5 CPU-minutes.
ASAN_EXCLUDE ?= ^mpi[.]|MirrorReflectsAboutItsShadingNormal$$|LampsLightOnASmoothMirrorLandsAsItsImageSays|SameMapsOnOneAndTwoThreads|BallLensFocusesAtTheParaxialFocalLength

.PHONY: demo test deps build build-asan test-asan bench clean format format-check

deps:
	@bash scripts/install-deps.sh

$(BUILD)/CMakeCache.txt:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

demo: build
	@mkdir -p $(OUT)
	$(BUILD)/propagate/propagate scenes/cornell.json --dry-run --report $(OUT)/cornell-dry-run.json
	$(BUILD)/propagate/propagate $(SCENE) $(DEMO_ARGS) -o $(OUT)/demo.vlf --report $(OUT)/demo-report.json
	$(BUILD)/walkthrough/walkthrough $(OUT)/demo.vlf --camera default --mode texture -o $(OUT)/demo-texture.png
	$(BUILD)/walkthrough/walkthrough $(OUT)/demo.vlf --camera default --mode texture -o $(OUT)/demo-texture.exr
	$(BUILD)/walkthrough/walkthrough $(OUT)/demo.vlf --camera default --mode raytrace -o $(OUT)/demo-raytrace.png
	$(BUILD)/walkthrough/walkthrough $(OUT)/demo.vlf --camera default --mode raytrace -o $(OUT)/demo-raytrace.exr
	@echo "demo: light-field statistics in $(OUT)/cornell-dry-run.json"
	@echo "demo: bake in $(OUT)/demo.vlf (lightmaps.exr opens in any EXR viewer), report in $(OUT)/demo-report.json"
	@echo "demo: images $(OUT)/demo-texture.png $(OUT)/demo-raytrace.png (tone-mapped) and .exr (linear)"

# Every test of the Release build, then the input-handling tests (scene loading and import,
# JSON, bundles, checkpoints, the command-line contract) again under ASan+UBSan.
test: format-check build build-asan
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)
	cd $(ASAN_BUILD) && ctest --output-on-failure -j $(JOBS) -E '$(ASAN_EXCLUDE)'

# -O1 -g1: ASan's reports keep file and line, and the build takes half the time of -O2 -g
# (the sanitized build was 14 of make test's 24 minutes).
build-asan: deps
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO='-O1 -g1 -DNDEBUG' -DVLF_SANITIZE=ON -DVLF_BUILD_BENCH=OFF -DVLF_BUILD_INTERACTIVE=OFF -DVLF_TEST_SET=$(ASAN_TEST_SET)
	cmake --build $(ASAN_BUILD) -j $(JOBS) --target vlf_tests propagate walkthrough

# Every test under ASan+UBSan (the whole test set: reconfigures build-asan).
test-asan: ASAN_TEST_SET = all
test-asan: build-asan
	cd $(ASAN_BUILD) && ctest --output-on-failure -j $(JOBS)

bench: build
	$(BUILD)/bench/vlf_bench --benchmark_min_time=0.2

# Every C++ file as .clang-format says: `make format` rewrites, `make format-check` (part
# of `make test`) fails naming each file that differs.
CXX_FILES = $$(git ls-files '*.cpp' '*.hpp')
format:
	clang-format -i $(CXX_FILES)

format-check: deps
	@clang-format --dry-run --Werror $(CXX_FILES) 2>&1 | grep -E '^[^ ].*: (error|warning):' | sed -E 's/:[0-9]+:[0-9]+: .*//' | sort -u | sed 's/$$/: differs from .clang-format (run `make format`)/' ; \
	  clang-format --dry-run --Werror $(CXX_FILES) > /dev/null 2>&1

clean:
	rm -rf $(BUILD) $(ASAN_BUILD)
