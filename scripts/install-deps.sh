#!/usr/bin/env bash
# Install the Debian packages lumis needs to build and test (only those missing).
set -euo pipefail

BASE=(build-essential cmake make pkg-config g++ libopenexr-dev libstb-dev libcjson-dev
      libpng-dev libcmocka-dev libembree-dev libassimp-dev ca-certificates python3
      python3-cffi python3-numpy python3-pytest)
DEV=(clang libclang-rt-14-dev libomp-dev clang-format chromium valgrind gcovr blender
     python3-clang-14)
SLURM=(slurm-wlm munge)

usage() {
    cat <<EOF
Usage: $(basename "$0") [--dev] [--slurm] [--data-tools] [--help]

Install with apt-get the Debian packages that are missing:
  ${BASE[*]}

  --dev         also the CI tools: ${DEV[*]}
                (clang + libFuzzer for 'make fuzz', clang-format for 'make format-check',
                chromium for the screenshot test of 'lumis bench' reports and the
                three.js test of the light exports, blender for their Blender test
                (python3-numpy, its glTF importer's, is in the base set: the Python
                package needs it too), valgrind for the memcheck
                stage, scripts/memcheck.sh, gcovr for 'make coverage', python3-clang-14
                for 'make mutate-diff' and 'make mutate-gen'), and nodejs
                and npm unless the node and npm commands exist; the consumer tests'
                npm packages then come from 'npm ci --prefix tests/consumers'
                (tests/consumers/run.sh)
  --slurm       also ${SLURM[*]}, for CI's cluster stage: a one-node Slurm
                (scripts/slurm-local.sh) runs a suite as job arrays (docs/cluster.md)
  --data-tools  also nodejs and npm (unless the node and npm commands already exist),
                which scripts/fetch-data.sh needs only when no local copy of the
                test data (../shared/data) exists
  --help        show this help

Runs as root, or through sudo otherwise. 'apt-get update' runs once, only if
something is missing.
EOF
}

WANT=("${BASE[@]}")
for arg in "$@"; do
    case "$arg" in
        --dev) WANT+=("${DEV[@]}")
            command -v node >/dev/null || WANT+=(nodejs)
            command -v npm >/dev/null || WANT+=(npm) ;;
        --slurm) WANT+=("${SLURM[@]}") ;;
        # By command, not package: some node packages (e.g. NodeSource's nodejs) bundle npm
        # and conflict with Debian's npm package.
        --data-tools)
            command -v node >/dev/null || WANT+=(nodejs)
            command -v npm >/dev/null || WANT+=(npm) ;;
        -h|--help) usage; exit 0 ;;
        *) echo "install-deps: unknown argument '$arg' (try --help)" >&2; exit 2 ;;
    esac
done

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q 'install ok installed'; }

MISSING=()
for pkg in "${WANT[@]}"; do
    installed "$pkg" || MISSING+=("$pkg")
done
if [[ ${#MISSING[@]} -eq 0 ]]; then
    echo "install-deps: all dependencies present"
    exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
    SUDO=()
elif command -v sudo >/dev/null; then
    SUDO=(sudo)
else
    echo "install-deps: error: missing packages (${MISSING[*]}), and this is neither root" \
         "nor has sudo; install them as root: apt-get install ${MISSING[*]}" >&2
    exit 1
fi

echo "install-deps: installing ${MISSING[*]}"
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y -q --no-install-recommends "${MISSING[@]}"
for pkg in "${MISSING[@]}"; do
    installed "$pkg" || { echo "install-deps: error: $pkg did not install" >&2; exit 1; }
    echo "install-deps: installed $pkg"
done
