# Sourced by .ci/app, .ci/test and .ci/run: what a fresh Debian/Ubuntu
# machine needs before it can build bump.
#
#   RUN_PACKAGES, TEST_PACKAGES  what running bump and testing it need.
#   install_packages PKG...  apt-get installs those not installed yet (as
#                            root, or through sudo); elsewhere it does nothing.
#   ensure_rust              puts cargo on PATH: the one there, else rustup's
#                            in ~/.cargo/bin, else a new stable toolchain from
#                            https://rustup.rs (with rustfmt and clippy); it
#                            fails, saying why, when none can be had or the
#                            one there is older than bump's minimum.

# The oldest Rust bump builds with: Cargo.toml's rust-version (the scripts
# run from the repository's root).
BUMP_MIN_RUST="$(sed -n 's/^rust-version = "\(.*\)"$/\1/p' Cargo.toml)"

# pkg-config, ALSA (the beep) and udev (joysticks) headers for -sys crates;
# Mesa's Vulkan driver (lavapipe) and loader, so bump renders on the CPU
# where there is no GPU driver; the X/Wayland client libraries winit loads.
RUN_PACKAGES=(pkg-config libasound2-dev libudev-dev mesa-vulkan-drivers libvulkan1 libx11-6 libxcursor1
  libxrandr2 libxi6 libxkbcommon0 libxkbcommon-x11-0 libwayland-client0)
# And an X server, xdotool and ImageMagick for the real-window test.
TEST_PACKAGES=("${RUN_PACKAGES[@]}" xvfb xauth xdotool imagemagick)

install_packages() {
  command -v apt-get >/dev/null 2>&1 || return 0
  local missing=() p
  for p in "$@"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
  done
  [ ${#missing[@]} -gt 0 ] || return 0
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "installing system packages: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
}

ensure_rust() {
  if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    export PATH="$HOME/.cargo/bin:$PATH"
  fi
  if ! command -v cargo >/dev/null 2>&1; then
    echo "cargo not found: installing Rust (stable, with rustfmt and clippy) from https://rustup.rs into ~/.cargo"
    install_packages curl ca-certificates
    if ! command -v curl >/dev/null 2>&1 ||
      ! curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs |
      sh -s -- -y -q --profile minimal -c rustfmt -c clippy --no-modify-path; then
      echo "could not install Rust: install it from https://rustup.rs (stable >= $BUMP_MIN_RUST) and run this again" >&2
      return 1
    fi
    export PATH="$HOME/.cargo/bin:$PATH"
  fi
  local have
  have="$(rustc --version 2>/dev/null | awk '{print $2}' || true)"
  if [ -z "$have" ] || [ "$(printf '%s\n%s\n' "$BUMP_MIN_RUST" "${have%%-*}" | sort -V | head -n 1)" != "$BUMP_MIN_RUST" ]; then
    echo "rustc ${have:-not found} is older than bump's minimum $BUMP_MIN_RUST: run 'rustup update stable'" >&2
    return 1
  fi
}
