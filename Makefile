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
# TODO(merge): add `--source spectral` (and `--source effective`) once the color module is merged.
LUT_SOURCES ?= --source three-channel
# `make luts ALL=1` works on every kept page instead of the 3d shelf.
ifeq ($(ALL),1)
SELECT    := --all
else
SELECT    := --shelf 3d
endif

.PHONY: all db build luts test bench clean

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

luts: db build
	$(NKLUT) --db $(DB) --out $(OUT) ingest $(SELECT)
	$(NKLUT) --db $(DB) --out $(OUT) bake $(SELECT) --size $(LUT_SIZE) $(LUT_SOURCES)

test: db
	$(CARGO) test

bench: db
	$(CARGO) bench --bench ingest

clean:
	rm -rf $(OUT)
