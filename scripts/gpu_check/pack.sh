#!/bin/bash
# Packs what a GPU machine without Rust needs to run the GPU tests and the bench presets:
# the test binaries and the app (release, stripped), this machine's Vulkan loader and Khronos
# validation layer, into DEST/bins.tar.xz (default .devcarry/, which .git/info/exclude should
# ignore), with run.sh beside it. Run from the repository root; see docs/src/building.md.
set -euo pipefail
DEST=${1:-.devcarry}
mkdir -p "$DEST"
STAGE=$(mktemp -d)
mkdir -p "$STAGE/bin" "$STAGE/vk"
# cargo prints one line per test binary: "Executable <target source> (<path>)".
cargo test --release --workspace --no-run 2>&1 |
    sed -n 's/^ *Executable \(.*\) (\(.*\))$/\1|\2/p' > "$STAGE/list"
while IFS='|' read -r source path; do
    crate=$(basename "$path" | sed 's/-[0-9a-f]*$//')
    case "$source" in
        # The library's and the app's GPU tests share a target name: tell them apart by a test.
        tests/gpu/main.rs)
            if "$path" --list 2>/dev/null | grep -q "^footprint_hull::"; then n=lib_gpu; else n=app_gpu; fi ;;
        "unittests src/lib.rs") n=${crate}_unit ;;
        *) n=$crate ;;
    esac
    # Not for a machine without cargo (external_dependent builds a crate) or without a GPU use.
    case "$source|$n" in
        "unittests src/main.rs|"* | *"|external_dependent" | *"|motion_shadows_shaderc_link_unit") continue ;;
    esac
    strip -o "$STAGE/bin/$n" "$path"
done < "$STAGE/list"
cargo build --release -p motion-shadows-app >/dev/null 2>&1
strip -o "$STAGE/bin/motion-shadows" target/release/motion-shadows
cp /usr/lib/x86_64-linux-gnu/libvulkan.so.1 /usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so "$STAGE/vk/"
sed 's#"library_path": "libVkLayer_khronos_validation.so"#"library_path": "./libVkLayer_khronos_validation.so"#' \
    /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json > "$STAGE/vk/VkLayer_khronos_validation.json"
ls "$STAGE/bin"
(cd "$STAGE" && tar cJf - bin vk) > "$DEST/bins.tar.xz"
cp scripts/gpu_check/run.sh "$DEST/run.sh"
rm -rf "$STAGE"
ls -la "$DEST"
