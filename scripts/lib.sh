# Shared by scripts/demo and scripts/test: install what is missing, configure, build.
# Sourced, not run.

ACDR_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ACDR_BUILD="${ACDR_BUILD:-$ACDR_ROOT/build}"

# Debian 12 packages the project builds and runs with (docs/dependencies.md).
ACDR_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libbullet-dev libeigen3-dev libsqlite3-dev nlohmann-json3-dev libimgui-dev libstb-dev
  libosmesa6-dev libglfw3-dev libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev
  libtinyobjloader-dev zlib1g-dev
  libcgal-dev libgmp-dev libmpfr-dev libsuitesparse-dev
  clang libclang-rt-14-dev
  xvfb xauth
)

acdr_install_missing() {
  local missing=()
  for p in "${ACDR_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "==> installing missing Debian packages: ${missing[*]}"
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "error: need root (or sudo) to install: ${missing[*]}" >&2; return 1; }
    sudo="sudo"
  fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

acdr_build() {
  echo "==> configuring (Release) in $ACDR_BUILD"
  cmake -S "$ACDR_ROOT" -B "$ACDR_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  echo "==> building"
  cmake --build "$ACDR_BUILD" -j"$(nproc)"
}
