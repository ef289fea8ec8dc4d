# The README's two commands: `make demo` and `make test`. Each does the whole set-up.
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
export VTK_DEFAULT_OPENGL_WINDOW := vtkEGLRenderWindow

.PHONY: demo test bench setup clean

$(STAMP): pyproject.toml constraints.txt tools/setup.sh
	bash tools/setup.sh

setup: $(STAMP)

demo: $(STAMP)
	$(PY) examples/demo.py

test: $(STAMP)
	$(PY) -m pytest -q -n 2 --dist loadfile

bench: $(STAMP)
	for script in bench/bench_*.py; do $(PY) $$script || exit 1; done

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache
