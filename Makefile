# Every target sets itself up: `make test` and `make run` work on a fresh machine.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
# The CPU wheel of torch 2.13.0 is what this project's machines carry; elsewhere override,
# e.g. `make setup TORCH_SPEC="torch>=2.4"` to keep a CUDA build already on the index.
TORCH_SPEC ?= torch==2.13.0
STAMP := $(VENV)/.installed

.PHONY: setup browser test lint run run-tiny report sensitivity bench bench-scale clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet "$(TORCH_SPEC)"
	$(BIN)/python -m pip install --quiet -e ".[test,vision,mllm]"
	touch $(STAMP)

# The questionnaire's click-through test (tests/test_userstudy.py) drives Debian's Chromium through
# Playwright (the test extra; no browser download). As root, install it when missing (about 30 s
# here); otherwise, or if apt cannot, that one test skips and says why.
CHROMIUM := /usr/bin/chromium

browser:
	@test -x $(CHROMIUM) || [ "$$(id -u)" != 0 ] || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
		apt-get install -y -qq --no-install-recommends chromium >/dev/null; } || echo "make: could not install chromium"

test: $(STAMP) browser
	$(BIN)/python -m pytest -q

# ruff (lint + format check), snakefmt, and the import layers of pyproject.toml (import-linter).
lint: $(STAMP)
	$(BIN)/ruff check capframe tests
	$(BIN)/ruff format --check capframe tests
	$(BIN)/snakefmt --check Snakefile workflow
	$(BIN)/lint-imports

run: $(STAMP)
	PATH="$(CURDIR)/$(BIN):$$PATH" $(BIN)/snakemake --workflow-profile workflow/profiles/default
	$(MAKE) report

# The workflow with Question-Evaluation on the MLLM backend, the image-text metrics and the two
# MLLM judges (config/tiny.yaml, config/models-tiny.yaml): tiny random-weight Qwen3-VL (two seeds),
# CLIP and SigLIP 2 built offline into .cache/, one scene. Meaningless answers and scores, real
# plumbing; a second run answers every request from the response cache.
TINY_MLLM := .cache/tiny-qwen3-vl/config.json
TINY_JUDGE := .cache/tiny-qwen3-vl-2/config.json
TINY_CLIP := .cache/tiny-clip/config.json
TINY_SIGLIP := .cache/tiny-siglip2/config.json

$(TINY_MLLM): $(STAMP)
	$(BIN)/python -c "from capframe.backends.tiny import tiny_qwen3_vl; tiny_qwen3_vl('$(dir $(TINY_MLLM))')"

$(TINY_JUDGE): $(STAMP)
	$(BIN)/python -c "from capframe.backends.tiny import tiny_qwen3_vl; tiny_qwen3_vl('$(dir $(TINY_JUDGE))', seed=1)"

$(TINY_CLIP): $(STAMP)
	$(BIN)/python -c "from capframe.backends.tiny import tiny_image_text; tiny_image_text('$(dir $(TINY_CLIP))', 'clip')"

$(TINY_SIGLIP): $(STAMP)
	$(BIN)/python -c "from capframe.backends.tiny import tiny_image_text; tiny_image_text('$(dir $(TINY_SIGLIP))', 'siglip')"

run-tiny: $(STAMP) $(TINY_MLLM) $(TINY_JUDGE) $(TINY_CLIP) $(TINY_SIGLIP)
	PATH="$(CURDIR)/$(BIN):$$PATH" $(BIN)/snakemake --workflow-profile workflow/profiles/default \
		--configfile config/config.yaml config/tiny.yaml

# The method's sensitivity variants (config/sensitivity.yaml) on top of a run, then the report.
sensitivity: $(STAMP)
	PATH="$(CURDIR)/$(BIN):$$PATH" $(BIN)/snakemake --workflow-profile workflow/profiles/default \
		--configfile config/config.yaml config/sensitivity.yaml
	PATH="$(CURDIR)/$(BIN):$$PATH" $(BIN)/snakemake --workflow-profile workflow/profiles/default \
		--configfile config/config.yaml config/sensitivity.yaml --report results/report.html

# The HTML report of a completed run: tables, the error-against-run-time plot, image grids.
report: $(STAMP)
	PATH="$(CURDIR)/$(BIN):$$PATH" $(BIN)/snakemake --workflow-profile workflow/profiles/default --report results/report.html

bench: $(STAMP)
	$(BIN)/capframe bench render
	$(BIN)/capframe bench refine
	$(BIN)/capframe bench ground
	$(BIN)/capframe bench models
	$(BIN)/capframe bench startup

# Not in bench: 0.3M to 3M Gaussians take tens of minutes on two cores.
bench-scale: $(STAMP)
	$(BIN)/capframe bench scale

clean:
	rm -rf results/* .snakemake
