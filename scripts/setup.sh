#!/usr/bin/env bash
# Installs the Debian 12 packages needed to build (shaderc, Vulkan headers) and to run the
# tests headless (lavapipe software Vulkan, Khronos validation layer). Idempotent: when all is
# present it only prints one line. May be run or sourced; it exports nothing.

# The body runs in a subshell so that, when sourced, neither `set -euo pipefail` nor `exit`
# leaks into the caller's shell.
motion_shadows_setup() (
    set -euo pipefail

    local packages=(
        mesa-vulkan-drivers
        libvulkan1
        libvulkan-dev
        vulkan-validationlayers
        libshaderc-dev
        glslang-dev
        spirv-tools
        pkg-config
        g++
    )

    local missing=()
    local pkg
    for pkg in "${packages[@]}"; do
        if [[ "$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)" != "install ok installed" ]]; then
            missing+=("$pkg")
        fi
    done

    if ((${#missing[@]} > 0)); then
        local sudo=()
        if ((EUID != 0)); then
            if command -v sudo >/dev/null 2>&1; then
                sudo=(sudo)
            else
                echo "setup.sh: need root or sudo to install: ${missing[*]}" >&2
                exit 1
            fi
        fi
        # apt prints progress on stdout; keep only errors (stderr) so the log stays short.
        "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq >/dev/null
        "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive \
            apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
        echo "setup.sh: installed ${missing[*]}" >&2
    else
        echo "setup.sh: all system packages present" >&2
    fi

    # The tests need these exact files, not just the packages: a package may have been
    # installed with its files removed, or a different Mesa build may lack lavapipe.
    if ! compgen -G '/usr/share/vulkan/icd.d/lvp_icd*.json' >/dev/null; then
        echo "setup.sh: lavapipe Vulkan ICD not found (/usr/share/vulkan/icd.d/lvp_icd*.json);" \
            "reinstall mesa-vulkan-drivers" >&2
        exit 1
    fi
    local layer=/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
    if [[ ! -f "$layer" ]]; then
        echo "setup.sh: Khronos validation layer manifest not found ($layer);" \
            "reinstall vulkan-validationlayers" >&2
        exit 1
    fi
)

if [[ "${BASH_SOURCE[0]}" != "$0" ]]; then
    motion_shadows_setup
    return
fi
set -euo pipefail
motion_shadows_setup
