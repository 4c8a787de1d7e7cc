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
# `make luts ALL=1` works on every kept page instead of the 3d shelf.
# validate over every page takes about 9 s and writes a 104 MB errors.csv that the report
# would then parse (BENCHMARKS.md), more than the 30 s budget of `ALL=1` leaves, so `ALL=1`
# leaves it to an explicit `nklut validate --all`; the manifest's per-row errors come from
# the bake.
ifeq ($(ALL),1)
SELECT    := --all
VALIDATE  := @echo "luts: skipping validate for ALL=1 (run: $(NKLUT) validate --all)"
else
SELECT    := --shelf 3d
VALIDATE  := $(NKLUT) --db $(DB) --out $(OUT) validate $(SELECT)
endif

.PHONY: all db build luts test test-deps bench gpu effects clean

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
# method errors, textures, then the report.
luts: db build
	$(NKLUT) --db $(DB) --out $(OUT) ingest $(SELECT)
	$(NKLUT) --db $(DB) --out $(OUT) colors $(SELECT)
	$(NKLUT) --db $(DB) --out $(OUT) params $(SELECT)
	$(VALIDATE)
	$(NKLUT) --db $(DB) --out $(OUT) bake $(SELECT) --size $(LUT_SIZE) $(LUT_SOURCES)
	$(NKLUT) --db $(DB) --out $(OUT) report $(SELECT)

# The system packages the tests need (lavapipe for the GPU tests, Chromium for the report's
# browser tests), installed by the one script CI uses too.
test-deps:
	bash scripts/test-deps

# The GPU tests run on any Vulkan adapter (lavapipe from mesa-vulkan-drivers here); with
# none they fail unless NKLUT_SKIP_GPU_TESTS=1.
test: db
	bash scripts/test-deps
	$(CARGO) test --features gpu

# Every benchmark of BENCHMARKS.md: ingest (wall + peak RSS), Fresnel methods, colours, report.
bench: db
	$(CARGO) bench --bench ingest
	$(CARGO) bench --bench fresnel -- --warm-up-time 1 --measurement-time 3
	$(CARGO) bench --bench colors
	$(CARGO) bench --bench params
	$(CARGO) bench --bench report

# The GPU measurements of scenes/default.yaml (timing + image error) → output/gpu_timing.csv,
# output/image_errors.csv. Meant for a machine with a GPU; `nklut gpu adapters` lists them.
gpu: db
	$(CARGO) run --release --features gpu -- --db $(DB) --out $(OUT) gpu run scenes/default.yaml

# The effects scenes on the CPU, one output folder each (output/<scene>/): multiple
# reflections and refractions (the f64 reference and the distance-map twin per Fresnel
# method → effects_errors.csv) and surfel ambient occlusion / indirect light (against the
# ray-traced reference → ao_errors.csv, ao_frames/). The AO scenes run with small
# reference ray counts (AO_RAYS per vertex, σ ≤ 1/32 per vertex) to keep the target short;
# raise AO_RAYS for figures.
EFFECTS_SCENES ?= teapot-in-a-box glass-sphere ao-bunny ao-sculpture ao-colour-bleeding
AO_RAYS ?= 256
effects: db build
	for scene in $(EFFECTS_SCENES); do \
	  $(NKLUT) --db $(DB) --out $(OUT)/$$scene effects --ao-rays $(AO_RAYS) scenes/$$scene.yaml || exit 1; \
	done

clean:
	rm -rf $(OUT)
