#!/usr/bin/env bash
# Fuzzes Caustic's file loaders with cargo fuzz (libFuzzer + AddressSanitizer).
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]
#
# Runs every target of fuzz/ (gltf, obj, ply, image), or the ones named, for
# SECONDS_PER_TARGET seconds each (default 60), one after the other. Seeds come from
# fuzz/corpus/TARGET (committed); what the fuzzer discovers goes to fuzz/work/TARGET
# (ignored by git) and is reused by the next run. Each run's log is fuzz/work/TARGET.log.
#
# Exits non-zero when a target crashes, panics, times out (10 s per input) or exceeds
# its memory limit (2048 MB; 4608 MB for image, which may legitimately decode a
# 16384 x 16384 RGBA float image, 4 GiB); the input is saved under
# fuzz/artifacts/TARGET/ and its panic message is printed. Reproduce with
#   cd fuzz && RUSTC_BOOTSTRAP=1 cargo fuzz run -O TARGET artifacts/TARGET/FILE
#
# Needs cargo-fuzz (`cargo install cargo-fuzz`). On a stable toolchain the nightly
# flags cargo fuzz passes (-Zsanitizer) are allowed with RUSTC_BOOTSTRAP=1, set here.
set -euo pipefail

seconds="${1:-60}"
shift || true
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root/fuzz"
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    targets=(gltf obj ply image scene_language)
fi
if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "cargo-fuzz is not installed: cargo install cargo-fuzz" >&2
    exit 2
fi
export RUSTC_BOOTSTRAP=1

echo "building fuzz targets (release, AddressSanitizer)..."
cargo fuzz build -O 2>&1 | tail -n 3 || { echo "build failed" >&2; exit 2; }

failed=()
printf '\n%-6s %8s %12s %9s %8s %s\n' target seconds executions "exec/s" corpus result
for target in "${targets[@]}"; do
    mkdir -p "work/$target" "artifacts/$target"
    log="work/$target.log"
    status=0
    memory=2048
    if [ "$target" = image ]; then
        memory=4608
    fi
    # -close_fd_mask=2 silences the loaders' warnings (libFuzzer and ASan keep their own
    # output); a crashing input is re-run below to show its panic message.
    cargo fuzz run -O "$target" "work/$target" "corpus/$target" -- \
        -max_total_time="$seconds" -timeout=10 -rss_limit_mb="$memory" -malloc_limit_mb="$memory" \
        -print_final_stats=1 -close_fd_mask=2 >"$log" 2>&1 || status=$?
    executions="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)"
    rate="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)"
    corpus="$(find "work/$target" -type f | wc -l)"
    result=ok
    if [ "$status" -ne 0 ]; then
        result="FAILED (exit $status)"
        failed+=("$target")
    fi
    printf '%-6s %8s %12s %9s %8s %s\n' "$target" "$seconds" "${executions:-?}" "${rate:-?}" "$corpus" "$result"
    if [ "$status" -ne 0 ]; then
        grep -E "^==[0-9]+==ERROR|^SUMMARY|panicked|Test unit written|ALARM|out-of-memory" "$log" | head -n 8 | sed 's/^/    /'
        artifact="$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -n 1)"
        if [ -n "$artifact" ] && [ -f "$artifact" ]; then
            echo "    panic message of $artifact:"
            cargo fuzz run -O "$target" "$artifact" 2>&1 | grep -E "panicked|^thread|ERROR" | head -n 4 | sed 's/^/      /' || true
        fi
    fi
done

if [ ${#failed[@]} -ne 0 ]; then
    echo "fuzzing found problems in: ${failed[*]} (logs in fuzz/work/, inputs in fuzz/artifacts/)" >&2
    exit 1
fi
echo "no crashes, panics, timeouts or memory blow-ups in ${#targets[@]} target(s) x ${seconds} s"
