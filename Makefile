# Two commands on a fresh machine: `make test` and `make book`. Both create .venv when it is missing.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: test test-all book book-check demo bench lint clean

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,book,browser,dev,fast,cluster]'
	touch $(STAMP)

test: $(STAMP)
	$(BIN)/python -m pytest -q -n 2 --dist worksteal

test-all: $(STAMP)
	$(BIN)/python -m pytest -q -m ""

book: $(STAMP)
	$(BIN)/python book/cache_key.py
	$(BIN)/jupyter-book build --warningiserror --keep-going book
	$(BIN)/python book/check_offline.py
	$(BIN)/python book/check_solutions.py
	@echo "book built: book/_build/html/index.html"

# every page of the built book in headless Chromium at 1280 px (Debian's chromium, installed where missing)
book-check: $(STAMP)
	command -v chromium >/dev/null || (apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y chromium)
	$(BIN)/python book/check_browser.py

demo: $(STAMP)
	$(BIN)/abrakit demo

bench: $(STAMP)
	$(BIN)/python benchmarks/run.py

lint: $(STAMP)
	$(BIN)/ruff check abrakit tests benchmarks examples

clean:
	rm -rf book/_build .pytest_cache
