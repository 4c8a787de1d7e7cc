# nklut — the two set-up commands on a fresh machine are `make luts` and `make test`.

SHARED_DB ?= ../shared/refractiveindex.info-database/database
UPSTREAM  ?= https://github.com/polyanskiy/refractiveindex.info-database.git
DB        := refractiveindex/database
OUT       ?= output
CARGO     ?= cargo
NKLUT     := target/release/nklut
# Bake settings of `make luts`: texels per row, and the sources (every encoding and both
# layouts are baked by default).
LUT_SIZE    ?= 256
# LUT sources: exact Fresnel of the three-channel index, and the spectral
# reference colour (add `--source effective` for the fitted effective indices).
LUT_SOURCES ?= --source three-channel --source spectral
# `make luts ALL=1` works on every kept page instead of the 3d shelf (validation included:
# its errors.csv over every page is ≈ 100 MB, which the report then reads).
ifeq ($(ALL),1)
SELECT    := --all
else
SELECT    := --shelf 3d
endif

.PHONY: all db build luts test test-deps test-blender bench gpu web effects report clean

all: luts

db: $(DB)/catalog-nk.yml

$(DB)/catalog-nk.yml:
	@if [ -d "$(SHARED_DB)" ]; then \
	  ln -sfn "$$(cd "$(SHARED_DB)" && pwd)" $(DB); \
	  echo "db: linked $(DB) -> $(SHARED_DB)"; \
	else \
	  git clone --depth 1 $(UPSTREAM) refractiveindex/upstream && \
	  ln -sfn upstream/database $(DB); \
	fi

build:
	$(CARGO) build --release

$(NKLUT): build

# The main job: tables, reference colours, engine parameters (+ MaterialX and glTF exports),
# method errors, textures, what to ship per page and device (`recommend`), then the report.
luts: db build
	$(NKLUT) --db $(DB) --out $(OUT) ingest $(SELECT)
	$(NKLUT) --db $(DB) --out $(OUT) colors $(SELECT)
	$(NKLUT) --db $(DB) --out $(OUT) params $(SELECT)
	$(NKLUT) --db $(DB) --out $(OUT) validate $(SELECT)
	$(NKLUT) --db $(DB) --out $(OUT) bake $(SELECT) --size $(LUT_SIZE) $(LUT_SOURCES)
	$(NKLUT) --db $(DB) --out $(OUT) recommend $(SELECT)
	$(NKLUT) --db $(DB) --out $(OUT) report $(SELECT)

# The system packages the tests need (lavapipe for the GPU tests, Chromium for the report's
# browser tests), installed by the one script CI uses too.
test-deps:
	bash scripts/test-deps

# Form first (rustfmt, clippy with warnings as errors, every target and feature), the
# optics crate packaged as it would be published (`cargo package`, built from the package),
# then the
# suite. The GPU tests run on any Vulkan adapter (lavapipe from mesa-vulkan-drivers here);
# with none they fail unless NKLUT_SKIP_GPU_TESTS=1.
test: db
	bash scripts/test-deps
	$(CARGO) fmt --check
	$(CARGO) clippy --workspace --all-targets --all-features -- -D warnings
	$(CARGO) package -p nklut-optics --allow-dirty --quiet
	$(CARGO) test --workspace --all-features

# Optional, not run by `make test` nor CI: Blender's own glTF importer as a client of
# materials.gltf. Blender runs as a Python module (PyPI `bpy`, pinned: a ≈ 375 MB wheel,
# ≈ 1 GB installed, hence kept out of `make test`) in its own venv .test-deps/blender-venv;
# bpy 5.0 is built for CPython 3.11 only (BLENDER_PYTHON names another interpreter). The 3d
# shelf is exported afresh into $(OUT)/blender-check, then tests/validators/check_blender.py
# imports it into an empty scene and checks, per page, what Blender's Principled BSDF and
# Volume Absorption hold against engine_params.csv (its docstring lists every assertion),
# and lists what the importer leaves out. Then clients/blender/nklut_lut.py's LUT node group:
# tests/clients/check_blender_lut.py renders spheres of four pages in five encodings with
# Cycles and holds every pixel's F to the manifest's maximum. Last, the paste-in blocks'
# Blender volume: tests/clients/check_blender_paste.py renders a 5 cm slab of every tinted
# page with the block's Volume Absorption Color and Density and holds what passes to the
# glTF path's attenuation colour^(0.05 m / distance) within 1e-5.
BPY_VERSION    ?= 5.0.1
BLENDER_PYTHON ?= python3
BLENDER_VENV   := .test-deps/blender-venv
test-blender: db build
	@[ -x $(BLENDER_VENV)/bin/python ] || $(BLENDER_PYTHON) -m venv $(BLENDER_VENV)
	@$(BLENDER_VENV)/bin/python -c "import importlib.metadata as m, sys; sys.exit(m.version('bpy') != '$(BPY_VERSION)')" 2>/dev/null || \
	  { echo "test-blender: installing bpy $(BPY_VERSION) into $(BLENDER_VENV) (≈ 375 MB download)"; \
	    $(BLENDER_VENV)/bin/pip install --quiet bpy==$(BPY_VERSION); }
	rm -rf $(OUT)/blender-check
	$(NKLUT) --db $(DB) --out $(OUT)/blender-check ingest --shelf 3d
	$(NKLUT) --db $(DB) --out $(OUT)/blender-check params --shelf 3d
	$(BLENDER_VENV)/bin/python tests/validators/check_blender.py $(OUT)/blender-check
	$(NKLUT) --db $(DB) --out $(OUT)/blender-check bake --size 256 --layout atlas --page 3d/metals/copper \
	  --page 3d/metals/gold --page 3d/glass/soda-lime-green --page 3d/liquids/water
	$(BLENDER_VENV)/bin/python tests/clients/check_blender_lut.py $(OUT)/blender-check/luts $(OUT)/blender-check/lut-renders
	$(BLENDER_VENV)/bin/python tests/clients/check_blender_paste.py $(OUT)/blender-check $(OUT)/blender-check/paste-renders

# Every benchmark of BENCHMARKS.md: the whole-database jobs beside their anchors (the
# plain file read, the Python peer of ingest), ingest (wall + peak RSS), Fresnel methods,
# colours, report.
bench: db
	$(CARGO) bench --bench whole_database
	$(CARGO) bench --bench ingest
	$(CARGO) bench --bench fresnel -- --warm-up-time 1 --measurement-time 3
	$(CARGO) bench --bench colors
	$(CARGO) bench --bench params
	$(CARGO) bench --bench report

# The GPU measurements. scenes/default.yaml: the F-only passes (timing + image error) →
# output/gpu_timing.csv, output/image_errors.csv. The reflection scenes: distance maps and
# the bounce loop on the GPU → output/gpu-<scene>/effects_timing.csv (map update and shading
# per configuration), effects_errors.csv (renderer gpu, against the f64 reference) and
# effects_gpu_frames/. Meant for a machine with a GPU; `nklut gpu adapters` lists them.
GPU_EFFECTS_SCENES ?= teapot-in-a-box glass-sphere
gpu: db
	$(CARGO) build --release --features gpu
	$(NKLUT) --db $(DB) --out $(OUT) gpu run scenes/default.yaml
	for scene in $(GPU_EFFECTS_SCENES); do \
	  $(NKLUT) --db $(DB) --out $(OUT)/gpu-$$scene gpu run scenes/$$scene.yaml || exit 1; \
	done

# The browser bench: one self-contained page per scene (output/web/<scene>.html) that runs
# the scene's F-only measurements (default) or its reflections' map update and shading pass
# (teapot-in-a-box: effects_timing) in any WebGPU browser and offers its result as JSON for
# benchmarks/devices/ (README, "The browser bench").
WEB_SCENES ?= scenes/default.yaml scenes/teapot-in-a-box.yaml
web: db
	$(CARGO) build --release --features gpu
	$(NKLUT) --db $(DB) --out $(OUT) gpu web $(WEB_SCENES)

# The effects scenes on the CPU, one output folder each (output/<scene>/): multiple
# reflections and refractions (the f64 reference and the distance-map twin per Fresnel
# method → effects_errors.csv), the spectral scenes (dispersion and absorption: the
# spectral reference against the three-channel one → spectral_errors.csv), and surfel
# ambient occlusion / indirect light with screen-space GTAO beside it (against the
# ray-traced reference → ao_errors.csv, ao_frames/). The AO scenes run with small
# reference ray counts (AO_RAYS per vertex, σ ≤ 1/32 per vertex) to keep the target short;
# raise AO_RAYS for figures.
EFFECTS_SCENES ?= teapot-in-a-box glass-sphere gold-in-gold prism coloured-glass ao-bunny ao-sculpture ao-colour-bleeding ao-bunny-gtao
AO_RAYS ?= 256
effects: db build
	for scene in $(EFFECTS_SCENES); do \
	  $(NKLUT) --db $(DB) --out $(OUT)/$$scene effects --ao-rays $(AO_RAYS) scenes/$$scene.yaml || exit 1; \
	done

# The whole picture in one command: the tables (`make luts`), the effects of every scene
# (`make effects`), the GPU results committed under benchmarks/devices/ (one folder per
# adapter, copied to $(OUT)/devices/), the recommendations again with those devices, then the
# report again so it draws from all of them:
# report/index.html and report/effects.html.
report: luts effects
	rm -rf $(OUT)/devices
	if [ -d benchmarks/devices ]; then cp -r benchmarks/devices $(OUT)/devices; fi
	$(NKLUT) --db $(DB) --out $(OUT) recommend $(SELECT)
	$(NKLUT) --db $(DB) --out $(OUT) report $(SELECT)

clean:
	rm -rf $(OUT)
