# `make demo` and `make test` set everything up on a fresh machine and reuse it afterwards.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
OUT    ?= runs/demo

.PHONY: setup demo test lint bench clean

setup: $(STAMP)

# torch and torchvision come as a matching pair from the package registry: `--isolated`
# keeps pip away from locally configured wheel folders that hold an unmatched torch build.
$(STAMP): pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip --isolated install --quiet $$(grep -E '^(torch|torchvision)==' constraints.txt)
	$(BIN)/pip install --quiet -c constraints.txt -e '.[dev]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/companion eval policy --episodes 100 --seed 0 --out $(OUT)

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/pytest

bench: $(STAMP)
	$(BIN)/python bench/bench_env.py

clean:
	rm -rf $(VENV) runs
