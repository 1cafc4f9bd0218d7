# VLF — the two set-up commands and a few conveniences.
#   make demo   install dependencies, Release build, run the main job on the default scene
#   make test   install dependencies, build, run every test (ctest)
BUILD       ?= build
ASAN_BUILD  ?= build-asan
JOBS        ?= $(shell nproc)
SCENE       ?= scenes/cornell-mirrors.json
DEMO_ARGS   ?= --quality preview
OUT         ?= out
ASAN_TESTS  ?= Scene|Primitive|Bake|Direction|Psf|Exchange|cli

.PHONY: demo test deps build build-asan test-asan bench clean format

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

# Every test of the Release build, then the input-handling tests (scene loading, bundles,
# the command-line contract) again under ASan+UBSan.
test: build build-asan
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)
	cd $(ASAN_BUILD) && ctest --output-on-failure -j $(JOBS) -R '$(ASAN_TESTS)'

build-asan: deps
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVLF_SANITIZE=ON -DVLF_BUILD_BENCH=OFF -DVLF_BUILD_INTERACTIVE=OFF
	cmake --build $(ASAN_BUILD) -j $(JOBS) --target vlf_tests propagate walkthrough

test-asan: build-asan
	cd $(ASAN_BUILD) && ctest --output-on-failure -j $(JOBS)

bench: build
	$(BUILD)/bench/vlf_bench --benchmark_min_time=0.2

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD) $(ASAN_BUILD)
