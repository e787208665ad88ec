#!/usr/bin/env bash
# The project's full check, as the README and CI run it: format, lints, then all tests on
# lavapipe with the Khronos validation layer (incl. synchronization validation) enabled.
#
#   scripts/test.sh           everything (CI runs this)
#   scripts/test.sh --quick   the edit loop: the same, without the slow tests named in
#                             scripts/slow-tests.txt (paper claims, bench presets, the
#                             outside-crate build)
set -euo pipefail

quick=0
case "${1:-}" in
    "") ;;
    --quick) quick=1 ;;
    *) echo "usage: scripts/test.sh [--quick]" >&2; exit 2 ;;
esac

cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh

# Mesa's device-select layer warns on every Vulkan instance when XDG_RUNTIME_DIR is unset
# (as in CI containers); a private directory silences it without affecting results.
if [[ -z "${XDG_RUNTIME_DIR:-}" ]]; then
    XDG_RUNTIME_DIR="$(mktemp -d /tmp/motion-shadows-xdg.XXXXXX)"
    trap 'rm -rf -- "$XDG_RUNTIME_DIR"' EXIT
fi
export XDG_RUNTIME_DIR
export MOTION_SHADOWS_VALIDATION=1
# The full check builds once from scratch (CI's fresh clone): incremental state would only
# take disk (3 GB of target/). The edit loop (--quick) keeps it.
if [[ $quick == 0 ]]; then
    export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
fi

cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
# The engine core alone (no research passes), as an engine with default-features = false
# builds it.
cargo clippy -p motion-shadows --lib --no-default-features -- -D warnings
# The library's API docs build without a warning (a broken intra-doc link fails here).
RUSTDOCFLAGS="-D warnings" cargo doc -p motion-shadows --no-deps --quiet
# The mutation list still applies to the tree (merges and renames drift its edits silently).
python3 scripts/mutants.py --check
if [[ $quick == 1 ]]; then
    skips=()
    while read -r name; do
        [[ -z $name || $name == \#* ]] || skips+=(--skip "$name")
    done < scripts/slow-tests.txt
    cargo test --workspace -- "${skips[@]}"
else
    cargo test --workspace
fi
