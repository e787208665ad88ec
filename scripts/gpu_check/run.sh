#!/bin/bash
# Runs on a GPU machine, from the repository root, what pack.sh packed: every GPU test binary
# with the validation layer (synchronization validation included), then bench presets one by
# one, within BUDGET_S seconds in all; results under $OUT (device.txt, summary.txt,
# test-logs.tar.gz, bench.tar.gz). The test binaries look for the repository where they were built
# (/work/main): a link there is made if that path is free.
set -u
ROOT=$PWD
DIR=$(cd "$(dirname "$0")" && pwd)
OUT=${OUT:-$ROOT/gpu-check-out}
LOGS=$(mktemp -d)
mkdir -p "$OUT"
# The device tool's recipe for the Vulkan loader and EGL (debs in .gl/, if carried).
for f in .gl/*.deb; do [ -f "$f" ] && dpkg -x "$f" /; done; ldconfig 2>/dev/null
START=$(date +%s)
DEADLINE=$((START + ${BUDGET_S:-450}))
left() { echo $((DEADLINE - $(date +%s))); }
cap() { local l; l=$(left); echo $(( l > $1 ? $1 : l )); }
mkdir -p /work && { [ -e /work/main ] || ln -s "$ROOT" /work/main; }
X=$DIR/x
mkdir -p "$X" && tar xJf "$DIR/bins.tar.xz" -C "$X"
mkdir -p target/release target/tmp && cp "$X/bin/motion-shadows" target/release/motion-shadows
export LD_LIBRARY_PATH=$X/vk VK_LAYER_PATH=$X/vk XDG_RUNTIME_DIR=/tmp
ICD=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -f "$ICD" ] && export VK_DRIVER_FILES=$ICD VK_ICD_FILENAMES=$ICD
{ nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; git log --oneline -1; } \
    > "$OUT/device.txt" 2>&1
export MOTION_SHADOWS_VALIDATION=1
{
for bin in "$X"/bin/*; do
    n=$(basename "$bin")
    [ "$n" = motion-shadows ] && continue
    dir=$ROOT/app; [ "$n" = lib_gpu ] && dir=$ROOT
    [ "$(left)" -le 5 ] && { echo "tests $n: skipped (time)"; continue; }
    t0=$(date +%s)
    (cd "$dir" && timeout "$(cap 200)" "$bin" --test-threads 8) > "$LOGS/$n.log" 2>&1
    rc=$?
    echo "tests $n: rc=$rc $(( $(date +%s) - t0 )) s: $(grep -E '^test result' "$LOGS/$n.log" | tail -1)"
    [ $rc -ne 0 ] && grep -E "panicked|FAILED|VUID" "$LOGS/$n.log" | head -20
done
} 2>&1 | tee "$OUT/summary.txt"
tar czf "$OUT/test-logs.tar.gz" -C "$LOGS" .
unset MOTION_SHADOWS_VALIDATION
mkdir -p bench
for p in ${PRESETS:-frame spp game shadow-pass equal-quality characters random-cubes speed cube-size scaling engine hard}; do
    l=$(left); [ "$l" -lt 15 ] && { echo "preset $p: skipped (time)" | tee -a "$OUT/summary.txt"; continue; }
    t0=$(date +%s)
    timeout "$l" ./target/release/motion-shadows bench --preset "$p" --out "bench/$p" > "bench/$p.txt" 2>&1
    echo "preset $p: rc=$? $(( $(date +%s) - t0 )) s" | tee -a "$OUT/summary.txt"
    grep -E "^  " "bench/$p.txt" | grep -v "wrote " | head -30
done
tar czf "$OUT/bench.tar.gz" bench
echo "total $(( $(date +%s) - START )) s"
