# The two commands of the README. Each sets up everything it needs on a fresh machine.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: serve test bench clean chromium

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

serve: $(STAMP)
	$(VENV)/bin/acs serve

# pytest exits 5 when it collected no test: make then fails, as CI must.
# The browser test drives Debian's chromium (Playwright's own browser download
# is never used).
test: $(STAMP) chromium
	$(PY) -m pytest -q

chromium:
	@command -v chromium >/dev/null || (apt-get update && apt-get install -y chromium)

bench: $(STAMP)
	$(VENV)/bin/acs bench

clean:
	rm -rf $(VENV) out build *.egg-info
