# The two set-up commands of the README. Each first makes sure a Vulkan driver exists.
CARGO ?= cargo

.PHONY: demo test vulkan xvfb

vulkan:
	@scripts/ensure-vulkan.sh

## Xvfb, for the viewer's window test (tests/viewer.rs).
xvfb:
	@scripts/ensure-xvfb.sh

## Render the default scene (the Cornell box) to cornell.png.
demo: vulkan
	$(CARGO) run --release -p caustic-cli -- render cornell --spp 64 -o cornell.png

## Run every unit and end-to-end test (renders on the Vulkan device, lavapipe on CPU machines;
## the viewer's window runs under Xvfb).
test: vulkan xvfb
	$(CARGO) test --release --workspace
