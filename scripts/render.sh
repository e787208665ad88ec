#!/usr/bin/env bash
# Renders with the release build; all arguments go to the motion-shadows binary.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

bash "$root/scripts/setup.sh"

# No `cd`: relative paths in the arguments (scenes, output files) keep meaning the caller's
# working directory.
cargo run --release --manifest-path "$root/Cargo.toml" -p motion-shadows-app -- "$@"
