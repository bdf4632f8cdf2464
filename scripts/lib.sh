# Shared by scripts/demo and scripts/test: install what is missing, configure, build.
# Sourced, not run.

ACDR_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ACDR_BUILD="${ACDR_BUILD:-$ACDR_ROOT/build}"

# Debian 12 packages the project builds and runs with (docs/dependencies.md).
ACDR_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libbullet-dev libeigen3-dev libsqlite3-dev nlohmann-json3-dev libimgui-dev libstb-dev
  libosmesa6-dev libglfw3-dev libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev
  libtinyobjloader-dev zlib1g-dev libcurl4-openssl-dev
  libcgal-dev libgmp-dev libmpfr-dev libsuitesparse-dev libxtst-dev
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

# The test learning record stores (tests/lrs: a validating endpoint built on Learning Locker's
# xapi-validation, and Learning Locker's statements service), from npm into tests/lrs/
# node_modules (ignored by git), as pinned by tests/lrs/package-lock.json. Only when node and
# npm exist; without them the tests that need a store say so and are skipped.
acdr_install_test_lrs() {
  local dir="$ACDR_ROOT/tests/lrs"
  if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    echo "==> node/npm not found: the xAPI sending tests against a test LRS will be skipped"
    return 0
  fi
  if [ -f "$dir/node_modules/.package-lock.json" ] &&
     [ "$dir/node_modules/.package-lock.json" -nt "$dir/package-lock.json" ]; then
    return 0
  fi
  echo "==> installing the test LRS packages (npm ci in tests/lrs)"
  (cd "$dir" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error) ||
    echo "warning: npm ci in tests/lrs failed: the xAPI sending tests will be skipped (they say why)"
}

acdr_build() {
  echo "==> configuring (Release) in $ACDR_BUILD"
  # ccache, when the machine has it, makes a rebuild in a second clone or worktree cheap.
  local launcher=()
  if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  fi
  cmake -S "$ACDR_ROOT" -B "$ACDR_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
  echo "==> building"
  cmake --build "$ACDR_BUILD" -j"$(nproc)"
  echo "==> built acdr $("$ACDR_BUILD/acdr" --version)"
}
