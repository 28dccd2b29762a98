# icerubble: the two commands a newcomer runs are `make demo` and `make test`.
PY      := /usr/bin/python3
BUILD   := build
SUDO    := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
DEBS    := yade gmsh python3-gmsh python3-numpy python3-scipy python3-matplotlib \
           python3-h5py python3-pybind11 pybind11-dev python3-pytest cmake g++ make \
           python3-pip python3-setuptools python3-wheel slurm-wlm munge
STAMP   := $(BUILD)/.built
# NATIVE=ON tunes the engine for this processor: a few % faster, but its
# results then differ in their bits from every other machine's (docs/reproducibility.md)
NATIVE  ?= OFF

.PHONY: setup deps build install test bench demo figures gpu-check clean

setup: deps build

# Debian packages only: YADE and the modules it sees live in /usr/bin/python3;
# slurm-wlm and munge for the cluster tests (a one-node SLURM started by the tests).
deps:
	@missing=$$(for p in $(DEBS); do dpkg -s $$p >/dev/null 2>&1 || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing:" $$missing; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; \
	fi

# The C++ engine and cohesive law (CMake), then the Python package installed in
# editable mode for /usr/bin/python3: `import icerubble` from any folder and
# inside yade, and the `icerubble` command (pyproject.toml).
build: deps
	cmake -S . -B $(BUILD) -DPython3_EXECUTABLE=$(PY) -DCMAKE_BUILD_TYPE=Release -DICERUBBLE_NATIVE=$(NATIVE) >/dev/null
	cmake --build $(BUILD) -j2
	@touch $(STAMP)
	@$(MAKE) --no-print-directory install

# Reinstalled only when this checkout is not the one installed.
install:
	@cd / && $(PY) -c "import icerubble, os, sys; sys.exit(os.path.dirname(os.path.dirname(icerubble.__file__)) != '$(CURDIR)')" 2>/dev/null \
	  && command -v icerubble >/dev/null || \
	  $(SUDO) $(PY) -m pip install --quiet --no-deps --no-build-isolation --break-system-packages --editable "$(CURDIR)"

test: deps build
	$(PY) -m pytest -q tests

bench: build
	$(PY) bench/run_all.py

demo: deps build
	$(PY) -m icerubble.cli demo

# Figs. 6-20 and Tables 2-3 from a folder of run results (docs/postproc.md)
RESULTS ?= results
FIGDIR  ?= figures
figures: build
	$(PY) -m icerubble.cli figures $(RESULTS) -o $(FIGDIR)

# The GPU backend against the CPU on a machine with a CUDA GPU and toolkit
# (docs/gpu.md); MESH: scene meshes to check and time on, e.g.
# runs/scenes/paper_ridge1_pilemu0.3_mesh.h5 (none: the built-in scenes only).
MESH ?=
gpu-check:
	PY=$(PY) tools/gpu_check.sh $(MESH)

clean:
	rm -rf $(BUILD) build-gpu icerubble/_*.so
