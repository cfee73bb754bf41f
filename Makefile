# `make demo` and `make test` set everything up on a fresh machine and reuse it afterwards.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
OUT    ?= runs/demo
WORLD  ?= worlds/living_room.yaml
WORDNET := /usr/share/wordnet/data.noun
SPHINXTRAIN := /usr/lib/sphinxtrain/map_adapt
FESTIVAL := /usr/share/festival/voices/us/cmu_us_slt_arctic_hts
PORTAUDIO := /usr/lib/x86_64-linux-gnu/libportaudio.so.2
RECORDINGS := /usr/share/pocketsphinx/test/data/librivox/fileids
SUDO   := $(if $(filter 0,$(shell id -u)),,sudo)

.PHONY: setup browser demo test lint bench snapshots clean

setup: $(STAMP) $(WORDNET) $(SPHINXTRAIN) $(FESTIVAL) $(PORTAUDIO) $(RECORDINGS) browser

# WordNet 3.0 (Debian's wordnet-base) answers the robot's everyday questions, read in place.
$(WORDNET):
	$(SUDO) apt-get update -qq
	DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends wordnet-base

# Adapting the speech recogniser's acoustic model (`companion train asr`, its tests) takes
# SphinxTrain's bw and map_adapt, sphinxbase's sphinx_fe and pocketsphinx's mdef converter,
# from Debian's packages; recognising speech needs none of them.
$(SPHINXTRAIN):
	$(SUDO) apt-get update -qq
	DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends \
	  sphinxtrain sphinxbase-utils pocketsphinx

# The held-out voices of `companion eval asr --voices held-out` (robot/voices/debian.py):
# CMU Flite with its built-in voices, and Festival with two voice packages.
$(FESTIVAL):
	$(SUDO) apt-get update -qq
	DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends \
	  flite festival festvox-kallpc16k festvox-us-slt-hts

# `companion chat --listen` reads the computer's microphone through sounddevice, which loads
# PortAudio (Debian's libportaudio2).
$(PORTAUDIO):
	$(SUDO) apt-get update -qq
	DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends libportaudio2

# People's own voices, recorded (`companion eval asr --recordings`): the test recordings of
# Debian's pocketsphinx-testdata and the English prompts of Asterisk's core sounds.
$(RECORDINGS):
	$(SUDO) apt-get update -qq
	DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends pocketsphinx-testdata \
	  asterisk-core-sounds-en asterisk-core-sounds-en-wav

# The tablet's browser tests (tests/test_tablet_browser.py) drive headless Chromium through
# its driver: Debian's chromium and chromium-driver (and a colour emoji font for the pages'
# icons in screenshots), installed with apt-get (with sudo when not root) unless both
# programs are already on the PATH.
browser:
	@command -v chromium >/dev/null && command -v chromedriver >/dev/null || { \
	  $(SUDO) apt-get update -qq && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver \
	    fonts-noto-color-emoji; }

# torch and torchvision come as a matching pair from the package registry: `--isolated`
# keeps pip away from locally configured wheel folders that hold an unmatched torch build.
# ultralytics pulls the GUI build of OpenCV; both builds own the `cv2` package, so the GUI
# one is removed and the headless one (same version) reinstalled over it.
$(STAMP): pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip --isolated install --quiet $$(grep -E '^(torch|torchvision)==' constraints.txt)
	$(BIN)/pip install --quiet -c constraints.txt -e '.[dev]'
	$(BIN)/pip uninstall --quiet -y opencv-python
	$(BIN)/pip install --quiet --force-reinstall --no-deps $$(grep -E '^opencv-python-headless==' constraints.txt)
	touch $(STAMP)

demo: setup
	$(BIN)/companion run $(WORLD) --out $(OUT) --overwrite

# lint-imports checks the import contracts of pyproject.toml (the layers of docs/architecture.md).
test: setup
	$(BIN)/ruff check .
	$(BIN)/lint-imports
	$(BIN)/pytest

# Refresh the behaviour-tree snapshots in tests/snapshots/ after an intended change.
snapshots: setup
	UPDATE_SNAPSHOTS=1 $(BIN)/pytest -q tests/test_tree_snapshots.py

bench: setup
	$(BIN)/python bench/bench_env.py

clean:
	rm -rf $(VENV) runs
