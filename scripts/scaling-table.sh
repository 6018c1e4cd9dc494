#!/usr/bin/env bash
# Measures the wall time of one render split by samples over N local processes, each started as
# an array element would be (JOB_COMPLETION_INDEX=i), then merged; prints a Markdown table.
#
#   scripts/scaling-table.sh [SCENE] [SIZE] [TOTAL_SPP] [REPEATS] [N...]
#   scripts/scaling-table.sh cornell 256x256 64 3 1 2 4      (the defaults)
#
# Each row is the best of REPEATS runs (interleaved over N); CPU time is user + system time of
# the render processes together. TOTAL_SPP must be divisible by
# every N.
set -euo pipefail
cd "$(dirname "$0")/.."
caustic=${CAUSTIC:-target/release/caustic}
scene=${1:-cornell}
size=${2:-256x256}
total=${3:-64}
repeats=${4:-3}
shift $(( $# < 4 ? $# : 4 ))
counts=("$@")
[[ ${#counts[@]} -gt 0 ]] || counts=(1 2 4)
[[ -x $caustic ]] || cargo build --release -p caustic-cli
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
now() { date +%s.%N; }

echo "caustic scaling: $scene $size, $total spp in total, $(nproc) cores, best of $repeats; adapter: $(
    "$caustic" render "$scene" --size 8x8 --spp 1 -o "$work/probe.exr" --json 2>/dev/null |
    sed -E 's/.*"adapter":"([^"]*)".*/\1/')"
echo
echo "| processes | spp each | render wall (s) | merge (s) | total wall (s) | speed-up | CPU time (s) |"
echo "|---:|---:|---:|---:|---:|---:|---:|"
declare -A best_render best_merge best_cpu
for n in "${counts[@]}"; do
    (( total / n * n == total )) || { echo "$total spp do not split over $n processes" >&2; exit 1; }
done
# Repeats outermost, so that a burst of load on a shared machine hits every N alike.
for _ in $(seq "$repeats"); do
    for n in "${counts[@]}"; do
        per=$((total / n))
        rm -f "$work"/part-*.exr "$work/merged.exr"
        start=$(now)
        pids=()
        for i in $(seq 0 $((n - 1))); do
            /usr/bin/time -f "%U %S" -o "$work/cpu-$i" \
                env -u SLURM_ARRAY_TASK_ID JOB_COMPLETION_INDEX="$i" "$caustic" render "$scene" --size "$size" \
                --samples-from-env --spp-per-task "$per" --tasks "$n" -o "$work/part-{index}.exr" 2>/dev/null &
            pids+=($!)
        done
        for pid in "${pids[@]}"; do wait "$pid"; done
        middle=$(now)
        "$caustic" merge "$work"/part-*.exr --samples "0..$total" -o "$work/merged.exr" 2>/dev/null
        end=$(now)
        render=$(echo "$middle - $start" | bc -l)
        merge=$(echo "$end - $middle" | bc -l)
        cpu=$(awk '{ total += $1 + $2 } END { print total }' "$work"/cpu-*)
        rm -f "$work"/cpu-*
        old=${best_render[$n]:-}
        if [[ -z $old ]] || (( $(echo "$render + $merge < $old + ${best_merge[$n]}" | bc -l) )); then
            best_render[$n]=$render best_merge[$n]=$merge best_cpu[$n]=$cpu
        fi
    done
done
base=""
for n in "${counts[@]}"; do
    sum=$(echo "${best_render[$n]} + ${best_merge[$n]}" | bc -l)
    [[ -n $base ]] || base=$sum
    printf "| %d | %d | %.2f | %.2f | %.2f | %.2fx | %.1f |\n" "$n" "$((total / n))" "${best_render[$n]}" \
        "${best_merge[$n]}" "$sum" "$(echo "$base / $sum" | bc -l)" "${best_cpu[$n]}"
done
echo
echo "load average after the runs: $(cut -d' ' -f1-3 /proc/loadavg)"
