#!/usr/bin/env bash
# Installs the system packages needed to build (shaderc, Vulkan headers) and to run the tests
# headless (lavapipe software Vulkan, Khronos validation layer) on Debian 12 or newer and on
# Ubuntu 24.04 or newer (read from /etc/os-release; the package names are the same on both).
# Idempotent: when all is present it only prints one line. May be run or sourced; it exports
# nothing.
#
# What is verified where (README, "CI for your own project"): Debian 12 is what this project
# is developed and tested on. The Ubuntu branch follows Ubuntu's package lists (24.04 ships
# every package below, in universe; 22.04 has no libshaderc-dev at all) and has not been run
# by the project.

# The body runs in a subshell so that, when sourced, neither `set -euo pipefail` nor `exit`
# leaks into the caller's shell.
motion_shadows_setup() (
    set -euo pipefail

    local id="" version="" like=""
    if [[ -r /etc/os-release ]]; then
        id="$(. /etc/os-release && echo "${ID:-}")"
        version="$(. /etc/os-release && echo "${VERSION_ID:-}")"
        like="$(. /etc/os-release && echo "${ID_LIKE:-}")"
    fi
    local major="${version%%.*}"
    case "$id" in
        debian)
            # Testing and unstable have no VERSION_ID: newer than 12.
            if [[ -n "$major" ]] && ((major < 12)); then
                echo "setup.sh: Debian $version is too old (need 12 or newer: shaderc, Vulkan 1.3)" >&2
                exit 1
            fi
            ;;
        ubuntu)
            if [[ -n "$major" ]] && ((major < 24)); then
                echo "setup.sh: Ubuntu $version has no libshaderc-dev package (Ubuntu ships it" \
                    "from 24.04 on); use Ubuntu 24.04 or newer, Debian 12, or build shaderc" \
                    "from source (README, Building notes)" >&2
                exit 1
            fi
            ;;
        *)
            if [[ " $like " != *" debian "* && " $like " != *" ubuntu "* ]]; then
                echo "setup.sh: unsupported system (${id:-no /etc/os-release}); install by hand:" \
                    "a Vulkan loader and headers, Mesa's lavapipe driver, the Khronos validation" \
                    "layer, shaderc and glslang static libraries, SPIRV-Tools, pkg-config, g++" >&2
                exit 1
            fi
            echo "setup.sh: $id is derived from Debian/Ubuntu ($like); using their package names" >&2
            ;;
    esac

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
        # `view` and its test: a window under a virtual X server, and the X libraries winit
        # loads at run time (it dlopens them: nothing at build time names them).
        xvfb
        libx11-6
        libx11-xcb1
        libxcursor1
        libxrandr2
        libxi6
        libxkbcommon-x11-0
        # The viewer's key test types into its window (XTEST).
        xdotool
        # scripts/test.sh checks the mutation list (scripts/mutants.py --check; tomllib: 3.11).
        python3
    )

    local missing=()
    local pkg
    for pkg in "${packages[@]}"; do
        if [[ "$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)" != "install ok installed" ]]; then
            missing+=("$pkg")
        fi
    done

    local sudo=()
    if ((EUID != 0)); then
        if command -v sudo >/dev/null 2>&1; then
            sudo=(sudo)
        elif ((${#missing[@]} > 0)); then
            echo "setup.sh: need root or sudo to install: ${missing[*]}" >&2
            exit 1
        fi
    fi

    if ((${#missing[@]} > 0)); then
        # apt prints progress on stdout; keep only errors (stderr) so the log stays short.
        "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq >/dev/null
        for pkg in "${missing[@]}"; do
            if ! apt-cache show "$pkg" >/dev/null 2>&1; then
                local hint=""
                if [[ "$id" == ubuntu ]]; then
                    hint=" (on Ubuntu it is in the universe component: add-apt-repository universe)"
                fi
                echo "setup.sh: no package $pkg in this system's apt sources$hint" >&2
                exit 1
            fi
        done
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

    pinned_rust
)

# The Rust of rust-toolchain.toml, under rustup (without rustup, cargo ignores that file). A
# machine whose `stable` already is the pinned version would otherwise fail every cargo
# command (rustup does not map `stable` to a version, and with RUSTUP_AUTO_INSTALL=0 or
# offline it cannot fetch one), and rustup refuses `toolchain link` under an official name:
# so the installed toolchain of that exact version, with rustfmt and clippy, gets the pinned
# name as a link in rustup's toolchain directory, which is what a link is to rustup. Only
# where no installed toolchain is that version does rustup download it.
pinned_rust() {
    command -v rustup >/dev/null 2>&1 || return 0
    local root channel host home
    root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
    channel="$(sed -n 's/^channel = "\(.*\)"$/\1/p' "$root/rust-toolchain.toml")"
    if [[ -z "$channel" ]]; then
        echo "setup.sh: no channel in $root/rust-toolchain.toml" >&2
        exit 1
    fi
    if (cd "$root" && rustc -V >/dev/null 2>&1); then
        return 0
    fi
    home="${RUSTUP_HOME:-$HOME/.rustup}"
    local toolchain installed
    while read -r toolchain _; do
        [[ -n "$toolchain" ]] || continue
        if [[ "$(rustup run "$toolchain" rustc -V 2>/dev/null)" == "rustc $channel "* ]]; then
            installed="$(rustup component list --installed --toolchain "$toolchain" 2>/dev/null)"
            if [[ "$installed" == *rustfmt* && "$installed" == *clippy* ]]; then
                host="$(rustup run "$toolchain" rustc -vV | sed -n 's/^host: //p')"
                ln -s "$(rustup run "$toolchain" rustc --print sysroot)" \
                    "$home/toolchains/$channel-$host"
                echo "setup.sh: Rust $channel (rust-toolchain.toml) is the installed" \
                    "$toolchain; linked under its version" >&2
                return 0
            fi
        fi
    done < <(rustup toolchain list)
    echo "setup.sh: installing Rust $channel (rust-toolchain.toml) with rustup" >&2
    if ! rustup toolchain install "$channel" --profile minimal -c rustfmt -c clippy \
        --no-self-update; then
        echo "setup.sh: rustup could not install Rust $channel, which rust-toolchain.toml" \
            "pins; install it (rustup toolchain install $channel -c rustfmt,clippy)" >&2
        exit 1
    fi
}

if [[ "${BASH_SOURCE[0]}" != "$0" ]]; then
    motion_shadows_setup
    return
fi
set -euo pipefail
motion_shadows_setup
