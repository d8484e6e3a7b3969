# scenerender developer tasks. `make test` is what CI runs (.ci/run).
PYTHON ?= python3
# pytest-xdist workers for `make test`: two keep both cores of a 2-core machine (CI's) busy,
# where one process leaves a core idle through single-threaded Python and NumPy and waits on
# child processes; 0 runs the suite in one process
TEST_WORKERS ?= 2

.PHONY: install test test-fast fuzz showcase goldens bench assets clean

install:
	$(PYTHON) -m pip install --quiet -e '.[test]'

test: install
	$(PYTHON) -m pytest -q -n $(TEST_WORKERS) --dist loadgroup

# everything except the tests that need an OpenGL context
test-fast: install
	$(PYTHON) -m pytest -q -m "not gl"

# many random scene, OBJ, MTL and image inputs (the normal test run tries a few fixed ones);
# FUZZ_EXAMPLES per test. Whatever it finds: fix it, then keep the input in tests/corpus/.
FUZZ_EXAMPLES ?= 5000
fuzz: install
	SCENERENDER_FUZZ=1 SCENERENDER_FUZZ_EXAMPLES=$(FUZZ_EXAMPLES) $(PYTHON) -m pytest -q tests/fuzz

showcase: install
	$(PYTHON) -m scenerender render scenes/showcase.yaml -o out/

# re-render the golden reference images after an intended visual change (look at them!)
goldens: install
	$(PYTHON) tests/golden_update.py

bench: install
	$(PYTHON) benchmarks/run.py

assets:
	$(PYTHON) scenes/assets/make_assets.py

clean:
	rm -rf out build dist .pytest_cache tests/output .hypothesis
