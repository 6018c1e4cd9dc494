# The set-up commands of the README. Each first makes sure what it needs exists.
CARGO ?= cargo

.PHONY: demo test lint vulkan xvfb

vulkan:
	@scripts/ensure-vulkan.sh

## Xvfb, for the viewer's window test (tests/viewer.rs).
xvfb:
	@scripts/ensure-xvfb.sh

## Render the default scene (the Cornell box) to cornell.png.
demo: vulkan
	$(CARGO) run --release -p caustic-cli -- render cornell --spp 64 -o cornell.png

## Formatting and lints as CI checks them: rustfmt, and clippy with every warning an error.
lint:
	@$(CARGO) clippy --version >/dev/null 2>&1 && $(CARGO) fmt --version >/dev/null 2>&1 || rustup component add clippy rustfmt
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets --release -- -D warnings

## Run the lints, then every unit and end-to-end test (renders on the Vulkan device, lavapipe
## on CPU machines; the viewer's window runs under Xvfb). Mesa keeps compiled kernels in a
## disk cache of 1 GiB by default, split into 50 parts of about 21 MB; the suite's kernels
## fill their parts past that and evict each other, so a run recompiles kernels the last one
## compiled (docs/PERFORMANCE.md, "the test suite"): the tests get 4 GiB unless the variable
## is set.
test: export MESA_SHADER_CACHE_MAX_SIZE ?= 4G
test: vulkan xvfb lint
	$(CARGO) test --release --workspace
