# Every target sets itself up: `make test` and `make run` work on a fresh machine.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
# The CPU wheel of torch 2.13.0 is what this project's machines carry; elsewhere override,
# e.g. `make setup TORCH_SPEC="torch>=2.4"` to keep a CUDA build already on the index.
TORCH_SPEC ?= torch==2.13.0
STAMP := $(VENV)/.installed

.PHONY: setup test lint run run-tiny report sensitivity bench bench-scale clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet "$(TORCH_SPEC)"
	$(BIN)/python -m pip install --quiet -e ".[test,vision,mllm]"
	touch $(STAMP)

test: $(STAMP)
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

# The workflow with the parser and Question-Evaluation on the MLLM backend (config/tiny.yaml): a
# tiny random-weight Qwen3-VL built offline into .cache/, one scene. Meaningless answers, real
# plumbing; a second run answers every request from the response cache.
TINY_MLLM := .cache/tiny-qwen3-vl/config.json

$(TINY_MLLM): $(STAMP)
	$(BIN)/python -c "from capframe.backends.tiny import tiny_qwen3_vl; tiny_qwen3_vl('$(dir $(TINY_MLLM))')"

run-tiny: $(STAMP) $(TINY_MLLM)
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
