# The set-up commands of the README. Each first makes sure what it needs exists.
CARGO ?= cargo

.PHONY: demo test lint lint-tools vulkan xvfb

vulkan:
	@scripts/ensure-vulkan.sh

## Xvfb, for the viewer's window test (tests/viewer.rs).
xvfb:
	@scripts/ensure-xvfb.sh

## Render the default scene (the Cornell box) to cornell.png.
demo: vulkan
	$(CARGO) run --release -p caustic-cli -- render cornell --spp 64 -o cornell.png

## Formatting and lints: rustfmt, and clippy with every warning an error (a check build).
lint: lint-tools
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets --release -- -D warnings

lint-tools:
	@$(CARGO) clippy --version >/dev/null 2>&1 && $(CARGO) fmt --version >/dev/null 2>&1 || rustup component add clippy rustfmt

## The same lints inside the test build: cargo hands the workspace's crates to clippy-driver
## (what `cargo clippy` does, with its CLIPPY_ARGS), which lints them as rustc compiles them, so
## the dependencies are compiled once instead of checked for clippy and then built again. The
## build covers clippy's `--all-targets` (libraries, their tests, binaries, integration tests;
## the workspace has no benches or examples). Artifacts built this way sit beside a plain
## build's under other hashes: neither evicts the other.
## Found when the recipe runs, after `lint-tools` has installed clippy; a run without it stops
## instead of building without the lints.
CLIPPY_DRIVER = $(shell rustup which clippy-driver 2>/dev/null || command -v clippy-driver)

## Check formatting, then build with the lints and run every unit and end-to-end test (renders
## on the Vulkan device, lavapipe on CPU machines; the viewer's window runs under Xvfb). Mesa
## keeps compiled kernels in a disk cache of 1 GiB by default, split into 50 parts of about
## 21 MB; the suite's kernels fill their parts past that and evict each other, so a run
## recompiles kernels the last one compiled (docs/PERFORMANCE.md, "the test suite"): the tests
## get 4 GiB unless the variable is set.
test: export MESA_SHADER_CACHE_MAX_SIZE ?= 4G
test: vulkan xvfb lint-tools
	$(CARGO) fmt --all -- --check
	@test -n "$(CLIPPY_DRIVER)" || { echo "make test: clippy-driver not found (rustup component add clippy)" >&2; exit 1; }
	RUSTC_WORKSPACE_WRAPPER="$(CLIPPY_DRIVER)" CLIPPY_ARGS=-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__ \
		$(CARGO) test --release --workspace
